//! Chromatic extinction: a medium with
//! `sigma_t_scale = [s_r, s_g, s_b]` must show, in channel c, what the same
//! medium with the single scale s_c shows — per pixel, under the z-test,
//! for `volpath` (spectral tracking), `direct` and `transmittance` with
//! several estimators — and achromatic scenes must not change.

use fogbank_image::image_io::Image;
use fogbank_image::metrics::ztest::ztest;
use fogbank_render::{parse_scene, render, Film, Progress, RenderOptions, Scene};
use std::path::Path;

const SCALES: [f32; 3] = [3.0, 9.0, 24.0];

fn build(text: &str, overrides: &[String]) -> Result<Scene, String> {
    let desc = parse_scene(text, "test", overrides).map_err(|e| e.0)?;
    Scene::build(desc, Path::new(".")).map_err(|e| e.0)
}

fn film(s: &Scene, spp: u32, seed: u32) -> Film {
    let opts = RenderOptions::new(spp, seed);
    render(s, &opts, &Progress::default()).film
}

/// Channel `c` of `from` (value and variance) into `into`.
fn splice_channel(into: &mut Image, from: &Image, c: usize) {
    let var = into.variance.as_mut().unwrap();
    let from_var = from.variance.as_ref().unwrap();
    for (i, p) in from.rgb.iter().enumerate() {
        into.rgb[i][c] = p[c];
        var[i][c] = from_var[i][c];
    }
}

/// A cloud with a tinted albedo and forward scattering, lit by a point
/// light and a sky.
fn scene(integrator: &str) -> String {
    format!(
        "[camera]\nfrom = [0, 0.3, 2.2]\nto = [0, 0, 0]\nwidth = 24\nheight = 16\nfov = 36\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 24, seed = 3 }}\n\
         albedo = [0.9, 0.8, 0.95]\nphase = {{ type = \"hg\", g = 0.4 }}\nfilter = \"trilinear\"\n\
         [[lights]]\ntype = \"point\"\nposition = [1, 1.5, 1]\nintensity = [3, 3, 3]\n\
         [[lights]]\ntype = \"constant\"\nradiance = [0.4, 0.5, 0.7]\n\
         [integrator]\n{integrator}\n"
    )
}

/// Channel c of the chromatic render against channel c of the render with
/// scale s_c, every channel under one z-test.
fn agrees_per_channel(integrator: &str, spp: u32) {
    let text = scene(integrator);
    let rgb = format!(
        "media.0.sigma_t_scale=[{}, {}, {}]",
        SCALES[0], SCALES[1], SCALES[2]
    );
    let chromatic = film(&build(&text, &[rgb]).unwrap(), spp, 1).mean_image();
    let mut reference = chromatic.clone();
    for (c, s) in SCALES.iter().enumerate() {
        let grey = build(&text, &[format!("media.0.sigma_t_scale={s}")]).unwrap();
        splice_channel(&mut reference, &film(&grey, spp, 2).mean_image(), c);
    }
    let z = ztest(&reference, &chromatic).unwrap();
    assert!(
        z.pass,
        "{integrator}: {} pixels fail (max |z| {:.2} at {:?}, threshold {:.2}), mean z {:?}",
        z.failing_pixels, z.max_abs_z, z.max_abs_z_pixel, z.threshold, z.mean_z
    );
    // The test has power: the channels differ a lot.
    let mean = |c: usize| chromatic.rgb.iter().map(|p| p[c] as f64).sum::<f64>();
    assert!(
        mean(0) > 1.2 * mean(2) || mean(2) > 1.2 * mean(0),
        "{integrator}: channels alike"
    );
}

#[test]
fn volpath_matches_each_channel_rendered_alone() {
    agrees_per_channel(
        "type = \"volpath\"\nmax_depth = 8\nestimator = \"ratio_tracking\"",
        256,
    );
}

#[test]
fn volpath_with_other_samplers_and_estimators_matches_each_channel() {
    agrees_per_channel(
        "type = \"volpath\"\nmax_depth = 4\ndistance_sampler = \"decomposition_tracking\"\nestimator = \"jackknife\"",
        192,
    );
    agrees_per_channel(
        "type = \"volpath\"\nmax_depth = 4\ndistance_sampler = \"regular_tracking\"\nestimator = \"track_length\"",
        192,
    );
}

#[test]
fn direct_matches_each_channel_rendered_alone() {
    agrees_per_channel(
        "type = \"direct\"\nestimator = \"residual_ratio_tracking\"",
        256,
    );
}

#[test]
fn transmittance_is_exact_per_channel_with_a_deterministic_estimator() {
    let text = scene("type = \"transmittance\"\nestimator = \"regular_tracking\"");
    let rgb = format!(
        "media.0.sigma_t_scale=[{}, {}, {}]",
        SCALES[0], SCALES[1], SCALES[2]
    );
    let chromatic = film(&build(&text, &[rgb]).unwrap(), 4, 1).mean();
    for (c, s) in SCALES.iter().enumerate() {
        let grey = film(
            &build(&text, &[format!("media.0.sigma_t_scale={s}")]).unwrap(),
            4,
            1,
        );
        for (i, p) in grey.mean().iter().enumerate() {
            let d = (p[c] - chromatic[i][c]).abs();
            assert!(
                d <= 1e-6 * p[c].max(1e-3),
                "pixel {i} channel {c}: {} vs {}",
                chromatic[i][c],
                p[c]
            );
        }
    }
}

/// The jackknife and ray marching estimate the three channels' τ from one
/// walk: a chromatic medium costs the lookups of the grey one at the
/// largest scale, and that channel's image is the grey image.
#[test]
fn jackknife_serves_every_channel_from_one_walk() {
    for e in ["jackknife", "ray_marching"] {
        let text = scene(&format!("type = \"transmittance\"\nestimator = \"{e}\""));
        let rgb = format!(
            "media.0.sigma_t_scale=[{}, {}, {}]",
            SCALES[0], SCALES[1], SCALES[2]
        );
        let chromatic = film(&build(&text, &[rgb]).unwrap(), 8, 1);
        let grey = film(
            &build(&text, &[format!("media.0.sigma_t_scale={}", SCALES[2])]).unwrap(),
            8,
            1,
        );
        assert_eq!(chromatic.lookups, grey.lookups, "{e}");
        assert!(grey.lookups > 0, "{e}");
        for (a, b) in chromatic.mean().iter().zip(grey.mean()) {
            assert!((a[2] - b[2]).abs() <= 1e-6, "{e}: {} vs {}", a[2], b[2]);
        }
    }
}

/// Albedo 1 under a uniform sky: every channel of every pixel reads the
/// sky's radiance, whatever the extinction (a white furnace for the
/// spectral-tracking weights).
#[test]
fn white_furnace_per_channel() {
    let text = "[camera]\nfrom = [0, 0, 2.2]\nto = [0, 0, 0]\nwidth = 12\nheight = 12\nfov = 30\n\
         [[media]]\ndensity = { procedural = \"cloud\", resolution = 16, seed = 5 }\n\
         sigma_t_scale = [2, 10, 40]\nalbedo = [1, 1, 1]\nfilter = \"trilinear\"\n\
         [[lights]]\ntype = \"constant\"\nradiance = [1, 1, 1]\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 100000\nrr_depth = 100000\n";
    let f = film(&build(text, &[]).unwrap(), 64, 7);
    let (mean, var) = (f.mean(), f.variance_of_mean());
    for c in 0..3 {
        let n = mean.len() as f64;
        let m = mean.iter().map(|p| p[c] as f64).sum::<f64>() / n;
        let se = (var.iter().map(|v| v[c] as f64).sum::<f64>()).sqrt() / n;
        assert!((m - 1.0).abs() < 4.0 * se + 1e-6, "channel {c}: {m} ± {se}");
    }
}

/// `density_rgb`: a 3-channel grid whose channels differ in shape, not
/// only in scale; channel c must match the render of channel c alone.
#[test]
fn rgb_density_grid_matches_each_channel_rendered_alone() {
    let dir = std::env::temp_dir().join(format!("fogbank-chroma-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let n = 12u32;
    let mut data = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let p = [i, j, k].map(|v| (v as f32 + 0.5) / n as f32 - 0.5);
                let r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
                let ball = (0.2 - r2).max(0.0) * 40.0;
                data.extend([
                    ball * (1.0 + 2.0 * p[0]),
                    ball * (1.0 - 2.0 * p[1]),
                    3.0 * p[2] + 1.5,
                ]);
            }
        }
    }
    let vol = dir.join("rgb.vol");
    fogbank_volume::loaders::vol::write_vol(
        &vol,
        [n; 3],
        3,
        [-0.5, -0.5, -0.5, 0.5, 0.5, 0.5],
        &data,
    )
    .unwrap();
    let text = |density: &str| {
        format!(
            "[camera]\nfrom = [0.3, 0.4, 2.0]\nto = [0, 0, 0]\nwidth = 20\nheight = 16\nfov = 40\n\
             [[media]]\ndensity = {{ vol = \"{}\"{density} }}\nsigma_t_scale = 2.5\n\
             albedo = [0.9, 0.7, 0.95]\nfilter = \"trilinear\"\nprecision = \"f32\"\n\
             [[lights]]\ntype = \"point\"\nposition = [1, 1.5, 1]\nintensity = [2, 2, 2]\n\
             [[lights]]\ntype = \"constant\"\nradiance = [0.4, 0.5, 0.7]\n\
             [integrator]\ntype = \"volpath\"\nmax_depth = 6\nestimator = \"ratio_tracking\"\n",
            vol.display()
        )
    };
    let rgb = build(&text(""), &["media.0.density_rgb=true".into()]).unwrap();
    let chromatic = film(&rgb, 256, 1).mean_image();
    let mut reference = chromatic.clone();
    for c in 0..3 {
        let one = build(&text(&format!(", channel = {c}")), &[]).unwrap();
        splice_channel(&mut reference, &film(&one, 256, 2).mean_image(), c);
    }
    std::fs::remove_dir_all(&dir).ok();
    let z = ztest(&reference, &chromatic).unwrap();
    assert!(
        z.pass,
        "{} pixels fail (max |z| {:.2} at {:?}, threshold {:.2}), mean z {:?}",
        z.failing_pixels, z.max_abs_z, z.max_abs_z_pixel, z.threshold, z.mean_z
    );
    let e = build(
        &text(""),
        &[
            "media.0.density_rgb=true".into(),
            "media.0.filter=\"nearest\"".into(),
        ],
    )
    .unwrap_err();
    assert!(e.contains("density_rgb"), "{e}");
}

#[test]
fn integrators_without_chromatic_support_refuse_it() {
    for ty in ["point_mis", "restir", "ament"] {
        let text = scene(&format!("type = \"{ty}\""));
        let e = build(&text, &["media.0.sigma_t_scale=[1, 2, 3]".into()]).unwrap_err();
        assert!(e.contains("chromatic"), "{ty}: {e}");
    }
    let text = scene("type = \"volpath\"\npins = \"all\"");
    let e = build(&text, &["media.0.sigma_t_scale=[1, 2, 3]".into()]).unwrap_err();
    assert!(e.contains("chromatic"), "{e}");
    let e = build(
        &scene("type = \"volpath\""),
        &["media.0.sigma_t_scale=[1, -2, 3]".into()],
    )
    .unwrap_err();
    assert!(e.contains("sigma_t_scale"), "{e}");
}

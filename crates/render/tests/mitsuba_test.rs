//! Mitsuba 3 XML scenes: fogbank renders `scenes/mitsuba/*.xml` as they
//! are and must agree with Mitsuba 3 `scalar_rgb` references of the same
//! files (made by `tools/mitsuba_refs.py` with 2.5·10⁷ samples and
//! per-pixel variance): Mitsuba's own render-test criterion
//! (Šidák-corrected per-pixel z-test at α = 0.01) plus each channel's image
//! mean within 1 % and 8×8-pixel block means within 2 % (relative L1), with
//! fogbank at 2·10⁶ samples per image or more for the noisiest scenes. And
//! the reader's refusals name file, line, tag and plugin.

use fogbank_image::image_io::{read_image, Image};
use fogbank_image::metrics::ztest::ztest;
use fogbank_render::{load_scene, render, Progress, RenderOptions};
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mitsuba")
}

/// Relative L1 distance of the 8×8 block means of channel `c`.
fn block_rel_l1(r: &Image, t: &Image, c: usize) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for by in (0..r.height).step_by(8) {
        for bx in (0..r.width).step_by(8) {
            let (mut a, mut b) = (0.0f64, 0.0f64);
            for y in by..(by + 8).min(r.height) {
                for x in bx..(bx + 8).min(r.width) {
                    a += r.rgb[y * r.width + x][c] as f64;
                    b += t.rgb[y * r.width + x][c] as f64;
                }
            }
            num += (a - b).abs();
            den += a.abs();
        }
    }
    num / den.max(1e-12)
}

/// A reference's record in `refs/refs.json`: its spp, the noise constant
/// of its 8×8 block relative L1 (≈ k / √samples) and that of its image
/// mean's relative standard error (largest channel).
fn reference_noise(name: &str) -> (f64, f64, f64) {
    let text = std::fs::read_to_string(scenes().join("refs/refs.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let s = &v["scenes"][name];
    let largest = |key: &str| {
        s[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .fold(0.0, f64::max)
    };
    let samples = s["samples"].as_f64().unwrap();
    (
        s["spp"].as_f64().unwrap(),
        largest("block8_rel_l1_x_sqrt_samples_rgb"),
        largest("mean_rel_se_rgb") * samples.sqrt(),
    )
}

fn agree(name: &str) {
    let reference = read_image(scenes().join(format!("refs/{name}.exr"))).unwrap();
    let pixels = reference.width * reference.height;
    // At least 2·10⁶ samples (Mitsuba's criterion), more where the scene is
    // so noisy that the other two would fail from noise alone: enough for
    // an expected block L1 of 1 % (half the limit) and for the image mean
    // to sit within 1 % at 3σ, allowing fogbank twice Mitsuba's variance
    // (it picks lights by power, Mitsuba uniformly).
    let (ref_spp, k_block, k_mean) = reference_noise(name);
    let ref_samples = ref_spp * pixels as f64;
    let block = 1.0 / ((0.01 / k_block).powi(2) - 1.0 / ref_samples);
    let mean = 2.0 * (3.0 * k_mean / 0.01).powi(2);
    let samples = block.max(mean).clamp(2e6, 2e7);
    let spp = (samples / pixels as f64).ceil() as u32;
    let scene = load_scene(Some(&scenes().join(format!("{name}.xml"))), &[]).unwrap();
    let film = render(
        &scene,
        &RenderOptions {
            spp,
            seed: 7,
            time_budget: None,
        },
        &Progress::default(),
    )
    .film;
    assert_eq!(film.nan_samples + film.inf_samples, 0, "{name}");
    // The test's variance of the mean is floored by the reference's
    // per-sample variance at the test's spp and by its own mean over the
    // pixel's 3×3 neighbourhood: a pixel whose rare bright samples the test
    // missed would otherwise have both its mean and its variance
    // underestimated and fail although unbiased (Mitsuba's own test judges
    // with the reference's per-sample variance alone; fogbank's samples can
    // be more skewed than Mitsuba's, as where it picks lights by power).
    let floor = ref_spp / spp as f64;
    let reference_var = reference.variance.clone().unwrap();
    let own = film.variance_of_mean();
    let (w, h) = (film.width as usize, film.height as usize);
    let local = |x: usize, y: usize, c: usize| {
        let (mut sum, mut n) = (0.0f64, 0.0f64);
        for yy in y.saturating_sub(1)..(y + 2).min(h) {
            for xx in x.saturating_sub(1)..(x + 2).min(w) {
                sum += own[yy * w + xx][c] as f64;
                n += 1.0;
            }
        }
        (sum / n) as f32
    };
    let variance = (0..w * h)
        .map(|i| {
            [0, 1, 2].map(|c| {
                own[i][c]
                    .max((reference_var[i][c] as f64 * floor) as f32)
                    .max(local(i % w, i / w, c))
            })
        })
        .collect();
    let test = Image {
        width: film.width as usize,
        height: film.height as usize,
        rgb: film.mean(),
        variance: Some(variance),
        is_srgb8: false,
    };
    let z = ztest(&reference, &test).unwrap();
    assert!(
        z.pass,
        "{name}: {} pixels fail the z-test (max |z| {:.2} at {:?}, threshold {:.2}); mean z {:?}",
        z.failing_pixels, z.max_abs_z, z.max_abs_z_pixel, z.threshold, z.mean_z
    );
    for c in 0..3 {
        let mean = |i: &Image| i.rgb.iter().map(|p| p[c] as f64).sum::<f64>() / i.rgb.len() as f64;
        let (r, t) = (mean(&reference), mean(&test));
        assert!(
            (t / r - 1.0).abs() < 0.01,
            "{name}: channel {c} mean {t} vs {r}"
        );
        let l1 = block_rel_l1(&reference, &test, c);
        assert!(
            l1 < 0.02,
            "{name}: channel {c} 8×8 blocks differ by {l1} (relative L1)"
        );
    }
}

#[test]
fn null_bounded_mesh_medium_agrees_with_mitsuba() {
    agree("null_mesh_medium");
}

#[test]
fn medium_behind_a_thin_dielectric_with_an_area_light_agrees_with_mitsuba() {
    agree("thin_area");
}

#[test]
fn light_inside_a_medium_agrees_with_mitsuba() {
    agree("light_in_medium");
}

#[test]
fn media_inside_smooth_and_rough_dielectrics_agree_with_mitsuba() {
    agree("dielectric_media");
}

#[test]
fn ground_under_a_cloud_in_sun_and_sky_agrees_with_mitsuba() {
    agree("cloud_ground");
}

#[test]
fn surfaces_under_an_environment_map_and_an_area_light_agree_with_mitsuba() {
    agree("surfaces_env_area");
}

#[test]
fn fog_among_many_small_emitters_agrees_with_mitsuba() {
    agree("fog_emitters");
}

#[test]
fn chromatic_homogeneous_and_gridded_media_agree_with_mitsuba() {
    agree("chromatic");
}

fn refusal(xml: &str) -> String {
    let dir = std::env::temp_dir().join(format!("fogbank-xml-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("t{}.xml", xml.len()));
    std::fs::write(&path, xml).unwrap();
    let Err(e) = load_scene(Some(&path), &[]) else {
        panic!("{} was accepted", path.display());
    };
    let e = e.0;
    assert!(e.contains(&path.display().to_string()), "{e}");
    e
}

#[test]
fn unsupported_plugins_and_parameters_are_refused_by_name_and_line() {
    let head = "<scene version=\"3.0.0\">\n";
    let e = refusal(&format!(
        "{head}<shape type=\"cube\">\n<bsdf type=\"roughplastic\"/>\n</shape>\n</scene>"
    ));
    assert!(e.contains(":3:") && e.contains("roughplastic"), "{e}");
    let e = refusal(&format!(
        "{head}<shape type=\"cube\">\n<bsdf type=\"diffuse\">\n<float name=\"roughness\" value=\"1\"/>\n</bsdf>\n</shape>\n</scene>"
    ));
    assert!(
        e.contains(":4:") && e.contains("roughness") && e.contains("diffuse"),
        "{e}"
    );
    let e = refusal(&format!("{head}<shape type=\"cube\"/>\n<bogus/>\n</scene>"));
    assert!(e.contains(":3:") && e.contains("<bogus"), "{e}");
    let e = refusal(&format!("{head}<shape type=\"cube\"\n</scene>"));
    assert!(e.contains("not well-formed"), "{e}");
    let e = refusal(&format!(
        "{head}<default name=\"r\" value=\"0.5\"/>\n<shape type=\"cube\"><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"$r, $g, 1\"/></bsdf></shape>\n</scene>"
    ));
    assert!(e.contains("$g"), "{e}");
    let e = refusal(&format!("{head}<integrator type=\"path\"/>\n</scene>"));
    assert!(e.contains("integrator `path`"), "{e}");
    let e = refusal(&format!(
        "{head}<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><film type=\"hdrfilm\"/></sensor>\n</scene>"
    ));
    assert!(e.contains("gaussian"), "{e}");
    let e = refusal(&format!(
        "{head}<include filename=\"missing.xml\"/>\n</scene>"
    ));
    assert!(e.contains("missing.xml"), "{e}");
}

#[test]
fn defaults_substitution_includes_and_refs() {
    let dir = std::env::temp_dir().join(format!("fogbank-xml-inc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("materials.xml"),
        "<scene version=\"3.0.0\"><bsdf type=\"diffuse\" id=\"grey\"><rgb name=\"reflectance\" value=\"$albedo\"/></bsdf></scene>",
    )
    .unwrap();
    let main = dir.join("main.xml");
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\">\n<default name=\"albedo\" value=\"0.25\"/>\n<include filename=\"materials.xml\"/>\n\
         <integrator type=\"moment\"><integrator type=\"volpath\"><integer name=\"max_depth\" value=\"3\"/></integrator></integrator>\n\
         <sensor type=\"perspective\"><float name=\"fov\" value=\"30\"/><transform name=\"to_world\"><lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>\n\
         <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"6\"/><rfilter type=\"box\"/></film></sensor>\n\
         <shape type=\"rectangle\"><ref id=\"grey\"/></shape>\n\
         <emitter type=\"directional\"><vector name=\"direction\" value=\"0, 0, -1\"/><rgb name=\"irradiance\" value=\"1\"/></emitter>\n</scene>",
    )
    .unwrap();
    let scene = load_scene(Some(&main), &[]).unwrap();
    let film = render(
        &scene,
        &RenderOptions {
            spp: 1,
            seed: 0,
            time_budget: None,
        },
        &Progress::default(),
    )
    .film;
    // The rectangle fills the centre: 0.25/π · 1 (the camera's +z looks at
    // its front).
    let c = film.mean()[3 * 8 + 4][0];
    assert!((c - 0.25 / std::f32::consts::PI).abs() < 1e-5, "{c}");
    assert_eq!(scene.camera.width, 8);
}

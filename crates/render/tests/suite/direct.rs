//! `direct` (single scattering) and medium emission against analytic
//! answers, and its identity with `volpath` at `max_depth = 1`.

use fogbank_math::Vec3;
use fogbank_render::world::blackbody::blackbody_rgb;
use fogbank_render::{parse_scene, render, Film, Progress, RenderOptions, Scene};
use std::path::Path;

const SIGMA: f64 = 3.0;
const RADIUS: f64 = 0.5;
const ALBEDO: f64 = 0.7;
const G: f64 = 0.5;
const LIGHT: [f64; 3] = [0.15, 0.1, 0.05];

/// A homogeneous sphere (radius ½, σ_t = 3) seen through 8×8 pixel centres,
/// lit by a unit point light inside it.
fn sphere_scene(integrator: &str, extra: &[&str]) -> Scene {
    let text = format!(
        "[camera]\nwidth = 8\nheight = 8\nfov = 24.0\n\
         [[media]]\ndensity = {{ procedural = \"sphere\", resolution = 32, value = 1.0, radius = {RADIUS} }}\n\
         sigma_t_scale = {SIGMA}\nalbedo = [{ALBEDO}, {ALBEDO}, {ALBEDO}]\nphase = {{ type = \"hg\", g = {G} }}\n\
         [[lights]]\ntype = \"point\"\nposition = [{}, {}, {}]\nintensity = [1.0, 1.0, 1.0]\n\
         [integrator]\ntype = \"{integrator}\"\n[render]\npixel_jitter = false\n",
        LIGHT[0], LIGHT[1], LIGHT[2]
    );
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    Scene::build(parse_scene(&text, "test", &extra).unwrap(), Path::new(".")).unwrap()
}

fn run(scene: &Scene, spp: u32, seed: u32) -> Film {
    let opts = RenderOptions::new(spp, seed);
    render(scene, &opts, &Progress::default()).film
}

fn hg(cos: f64) -> f64 {
    let d = 1.0 + G * G - 2.0 * G * cos;
    (1.0 - G * G) / (4.0 * std::f64::consts::PI * d * d.sqrt())
}

/// The camera ray's chord [t0, t1] through the sphere, if any.
fn chord(o: [f64; 3], d: [f64; 3]) -> Option<(f64, f64)> {
    let od: f64 = (0..3).map(|i| o[i] * d[i]).sum();
    let oo: f64 = (0..3).map(|i| o[i] * o[i]).sum();
    let disc = od * od - (oo - RADIUS * RADIUS);
    (disc > 0.0).then(|| (-od - disc.sqrt(), -od + disc.sqrt()))
}

/// Single scattering by quadrature: ∫ e^{−σ(t−t0)} σ a f(θ) I/r² e^{−σ r} dt
/// (the light is inside the sphere, so its whole shadow segment is too).
fn single_scattering(o: [f64; 3], d: [f64; 3]) -> f64 {
    let Some((t0, t1)) = chord(o, d) else {
        return 0.0;
    };
    let n = 200_000;
    let h = (t1 - t0) / n as f64;
    let mut sum = 0.0;
    for i in 0..n {
        let t = t0 + (i as f64 + 0.5) * h;
        let x: Vec<f64> = (0..3).map(|k| o[k] + t * d[k]).collect();
        let l: Vec<f64> = (0..3).map(|k| LIGHT[k] - x[k]).collect();
        let r = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        let cos = (l[0] * d[0] + l[1] * d[1] + l[2] * d[2]) / r;
        sum += (-SIGMA * (t - t0)).exp() * SIGMA * ALBEDO * hg(cos) / (r * r) * (-SIGMA * r).exp();
    }
    sum * h
}

fn pixel_ray(scene: &Scene, x: u32, y: u32) -> ([f64; 3], [f64; 3]) {
    let r = scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
    let d = r.d.normalize();
    (r.o.as_dvec3().to_array(), d.as_dvec3().to_array())
}

/// Every pixel's mean within 4.5 standard errors (plus f32 slack) of `reference`.
fn assert_matches(film: &Film, reference: impl Fn(u32, u32) -> f64, what: &str) {
    let mut nonzero = 0;
    for y in 0..film.height {
        for x in 0..film.width {
            let i = (y * film.width + x) as usize;
            let n = film.count[i] as f64;
            let mean = film.sum(i)[0] / n;
            let se = ((film.sum_sq(i)[0] / n - mean * mean).max(0.0) / n).sqrt();
            let r = reference(x, y);
            nonzero += (r > 0.0) as u32;
            assert!(
                (mean - r).abs() <= 4.5 * se + 2e-4 * r,
                "{what}: pixel ({x}, {y}) mean {mean:.6} ± {se:.6} vs exact {r:.6}"
            );
        }
    }
    assert!(nonzero >= 40, "{what}: the sphere covers too few pixels");
    assert_eq!(film.nan_samples + film.inf_samples, 0);
}

#[test]
fn single_scattering_in_a_homogeneous_sphere_matches_quadrature() {
    let probe = sphere_scene("direct", &[]);
    let mut exact = vec![0.0; 64];
    for y in 0..8 {
        for x in 0..8 {
            let (o, d) = pixel_ray(&probe, x, y);
            exact[(y * 8 + x) as usize] = single_scattering(o, d);
        }
    }
    for (integrator, sampler, nee) in [
        ("direct", "delta_tracking", "ratio_tracking"),
        ("direct", "decomposition_tracking", "track_length"),
        ("direct", "delta_tracking", "residual_ratio_tracking"),
        ("direct", "delta_tracking", "unbiased_ray_marching"),
        ("volpath", "delta_tracking", "ratio_tracking"),
    ] {
        let mut extra = vec![
            format!("integrator.distance_sampler={sampler}"),
            format!("integrator.estimator={nee}"),
        ];
        if integrator == "volpath" {
            extra.push("integrator.max_depth=1".into());
        }
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        let film = run(&sphere_scene(integrator, &extra), 4096, 3);
        assert_matches(
            &film,
            |x, y| exact[(y * 8 + x) as usize],
            &format!("{integrator} {sampler} + {nee}"),
        );
    }
}

/// An emitting, purely absorbing sphere without lights: each pixel sees
/// (1 − a) L_e (1 − e^{−σ c}) for chord length c (with a = 0 first, then the
/// first collision of a scattering medium at max_depth = 1).
#[test]
fn emission_matches_the_closed_form() {
    let probe = sphere_scene("direct", &[]);
    let closed = |x: u32, y: u32, a: f64, le: f64| {
        let (o, d) = pixel_ray(&probe, x, y);
        chord(o, d).map_or(0.0, |(t0, t1)| {
            (1.0 - a) * le * (1.0 - (-SIGMA * (t1 - t0)).exp())
        })
    };
    let no_light = "lights=[]";
    for (integrator, albedo, emission, le) in [
        ("direct", 0.0, "{ color = [2.0, 2.0, 2.0] }", 2.0),
        (
            "volpath",
            0.0,
            "{ color = [1.0, 1.0, 1.0], scale = 2.0 }",
            2.0,
        ),
        ("direct", 0.6, "{ color = [2.0, 2.0, 2.0] }", 2.0),
        (
            "direct",
            0.0,
            "{ temperature = { procedural = \"constant\", value = 6500.0 } }",
            blackbody_rgb(6500.0).x as f64,
        ),
    ] {
        let scene = sphere_scene(
            integrator,
            &[
                no_light,
                &format!("media.0.albedo=[{albedo}, {albedo}, {albedo}]"),
                &format!("media.0.emission={emission}"),
            ],
        );
        let film = run(&scene, 2048, 5);
        assert_matches(
            &film,
            |x, y| closed(x, y, albedo, le),
            &format!("{integrator} emission {emission} albedo {albedo}"),
        );
    }
}

/// A cloud under an environment plus a point light: `direct` is `volpath`
/// with `max_depth = 1`, sample for sample.
#[test]
fn direct_equals_volpath_at_depth_one() {
    let text = "[camera]\nwidth = 10\nheight = 8\n\
                [[media]]\ndensity = { procedural = \"cloud\", resolution = 24, seed = 4 }\nsigma_t_scale = 15.0\n\
                phase = { type = \"hg\", g = 0.4 }\n\
                [[lights]]\ntype = \"constant\"\nradiance = [0.5, 0.6, 0.7]\n\
                [[lights]]\ntype = \"point\"\nposition = [0.3, 0.8, 0.2]\nintensity = [2.0, 1.0, 1.0]\n\
                [integrator]\ntype = \"direct\"\nestimator = \"jackknife\"\n";
    let build = |extra: &[&str]| {
        let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
        Scene::build(parse_scene(text, "t", &extra).unwrap(), Path::new(".")).unwrap()
    };
    let a = run(&build(&[]), 8, 9);
    let b = run(
        &build(&["integrator.type=volpath", "integrator.max_depth=1"]),
        8,
        9,
    );
    assert_eq!(a.sums, b.sums);
    assert_eq!(a.lookups, b.lookups);
    assert!((0..a.sums.len()).any(|i| a.sum(i)[0] > 0.0));
}

/// An albedo grid that is constant 0.5 times a white tint is the constant
/// albedo 0.5, sample for sample.
#[test]
fn constant_albedo_grid_equals_constant_albedo() {
    let grid = sphere_scene(
        "volpath",
        &[
            "media.0.albedo=[1.0, 1.0, 1.0]",
            "media.0.albedo_grid={ procedural = \"constant\", value = 0.5 }",
        ],
    );
    let constant = sphere_scene("volpath", &["media.0.albedo=[0.5, 0.5, 0.5]"]);
    assert_eq!(run(&grid, 4, 1).sums, run(&constant, 4, 1).sums);
    // A grid above 1 clamps to albedo 1.
    let m = &grid.media[0];
    assert_eq!(m.albedo_at(Vec3::ZERO), Vec3::splat(0.5));
    assert_eq!(m.albedo_at(Vec3::splat(5.0)), Vec3::ZERO);
}

#[test]
fn bad_medium_properties_are_named() {
    let text = "[[media]]\ndensity = { procedural = \"constant\" }\n";
    let err = |extra: &[&str]| {
        let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
        match parse_scene(text, "t", &extra) {
            Err(e) => e.0,
            Ok(d) => Scene::build(d, Path::new(".")).expect_err("must fail").0,
        }
    };
    assert!(err(&["media.0.albedo=[1.5, 0.5, 0.5]"]).contains("media.0.albedo"));
    let e = err(&["media.0.emission={ grid = { procedural = \"constant\" }, temperature = { procedural = \"constant\" } }"]);
    assert!(
        e.contains("media.0.emission") && e.contains("not both"),
        "{e}"
    );
    assert!(err(&["media.0.emission={ colour = [1, 1, 1] }"]).contains("colour"));
    assert!(err(&["media.0.albedo_grid={ vol = \"missing.vol\" }"]).contains("media.0.albedo_grid"));
    let e = err(&[
        "media.0.density.procedural=sphere",
        "media.0.density.radius=0.9",
    ]);
    assert!(e.contains("sphere"), "{e}");
}

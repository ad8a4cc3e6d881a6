//! The ray-marched baseline `ament` (AZD17, Lerzer and Dachsbacher 2025 §4): unoptimised it is
//! the same single-scattering DVR `visopt` estimates (its deterministic
//! expectation), and Fig. 2 as a test: the printed form's μ'/μ shrinks with
//! the step (Eq. 5), the Δx-normalised form does not move.

use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::Path;

const SCENE: &str = include_str!("../scenes/ament_cloud.toml");

fn scene(extra: &[&str]) -> Scene {
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let desc = parse_scene(SCENE, "test", &extra).unwrap();
    Scene::build(desc, Path::new(".")).unwrap()
}

#[test]
fn printed_form_vanishes_as_the_step_shrinks_and_normalised_does_not() {
    let mean_factor = |form: &str, step: f32| -> f64 {
        let s = scene(&[
            "integrator.type=\"ament\"",
            &format!("integrator.form=\"{form}\""),
            &format!("integrator.step={step}"),
        ]);
        let IntegratorKind::Ament(a) = &s.integrator else {
            panic!()
        };
        let f = a.factors(&s.world, 5, 4);
        assert!(f.len() > 10, "{form} {step}: {} samples", f.len());
        f.iter().map(|(_, v)| *v as f64).sum::<f64>() / f.len() as f64
    };
    let printed: Vec<f64> = [0.01, 0.001, 0.0001]
        .iter()
        .map(|&s| mean_factor("printed", s))
        .collect();
    let normalised: Vec<f64> = [0.01, 0.001, 0.0001]
        .iter()
        .map(|&s| mean_factor("normalised", s))
        .collect();
    // Eq. 5: more samples, larger sums, μ' → 0.
    assert!(
        printed[1] < 0.3 * printed[0] && printed[2] < 0.3 * printed[1],
        "printed {printed:?}"
    );
    assert!(printed[2] < 0.01, "printed {printed:?}");
    // Σ g² Δx approximates ∫ k²: the factor converges.
    assert!(
        (normalised[1] - normalised[2]).abs() < 0.02 * normalised[2],
        "normalised {normalised:?}"
    );
    assert!(normalised[2] > 0.05, "normalised {normalised:?}");
}

#[test]
fn unoptimised_marching_is_the_dvr_visopt_estimates() {
    for shading in ["false", "true"] {
        let a = scene(&[
            "integrator.type=\"ament\"",
            "integrator.optimise=false",
            "integrator.step=0.002",
            &format!("integrator.shading={shading}"),
        ]);
        let image = render(&a, &RenderOptions::new(1, 1), &Progress::default())
            .film
            .mean();
        let v = scene(&[
            "integrator.type=\"visopt\"",
            "integrator.optimise=false",
            "integrator.light_samples=0",
            &format!("integrator.shading={shading}"),
        ]);
        let IntegratorKind::VisOpt(vo) = &v.integrator else {
            panic!()
        };
        let (w, h) = (v.camera.width, v.camera.height);
        let top = image.iter().map(|p| p[0]).fold(0.0f32, f32::max);
        assert!(top > 0.01);
        for i in 0..w * h {
            let expected = vo
                .expected_pixel(&v.world, i % w, i / w, 1.0 / 1024.0, 1.0 / 256.0)
                .unwrap()
                .x;
            let got = image[i as usize][0];
            assert!(
                (got - expected).abs() < 0.01 * top,
                "shading {shading}, pixel {i}: marched {got}, expected {expected}"
            );
        }
    }
}

#[test]
fn bad_settings_are_refused() {
    let err = |extra: &[&str]| {
        let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
        match parse_scene(SCENE, "test", &extra) {
            Err(e) => e.to_string(),
            Ok(d) => Scene::build(d, Path::new("."))
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
        }
    };
    assert!(
        err(&["integrator.type=\"ament\"", "integrator.form=\"sum\""]).contains("integrator.form")
    );
    assert!(err(&["integrator.type=\"ament\"", "integrator.step=0.0"]).contains("integrator.step"));
    assert!(err(&["integrator.type=\"ament\"", "integrator.step=1e-7"]).contains("10⁶"));
}

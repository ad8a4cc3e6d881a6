//! Lerzer and Dachsbacher 2025 on the GPU: `visopt` with the CPU's frozen
//! camera lists, importance rules of every kind, NEE lists built on the
//! device, the gradient lobe and the three scattering settings — per-pixel
//! z-test against the CPU on lavapipe; `ament`, deterministic, pixel for
//! pixel to 2·10⁻³.
//!
//! Steps and list sizes are coarse because lavapipe (Mesa 22's gallivm)
//! stops every loop of an invocation once all of them together have run
//! 65535 iterations (`LP_MAX_TGSI_LOOP_ITERATIONS`, shared by every loop
//! of a shader): Ament's marches at its default step, a shadow march per
//! sample, exceed that and come back truncated on lavapipe only.

use fogbank_gpu::{render as gpu_render, test_gpu};
use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::Path;

use crate::support;
use support::assert_gpu_matches_cpu;

const SCENE: &str = include_str!("../scenes/visopt_cloud.toml");

/// Opaque black occluders (occluders.wgsl): one square hides part of the
/// view, one shadows part of the cloud from the light.
const OCCLUDERS: &str = include_str!("../scenes/visopt_occluders.toml");

fn scene(extra: &[&str]) -> Scene {
    scene_of(SCENE, extra)
}

fn scene_of(text: &str, extra: &[&str]) -> Scene {
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let desc = parse_scene(text, "test", &extra).unwrap();
    Scene::build(desc, Path::new(".")).unwrap()
}

#[test]
fn visopt_and_ament_with_occluders_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let text = format!("{SCENE}{OCCLUDERS}");
    let s = scene_of(
        &text,
        &["integrator.type=\"visopt\"", "integrator.light_samples=16"],
    );
    assert_gpu_matches_cpu(&gpu, &s, 48, 0.005, "visopt with occluders");
    let s = scene_of(
        &text,
        &[
            "integrator.type=\"ament\"",
            "integrator.step=0.1",
            "integrator.jitter=true",
        ],
    );
    assert_gpu_matches_cpu(&gpu, &s, 32, 0.005, "ament with occluders");
}

#[test]
fn visopt_matches_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let v = "integrator.type=\"visopt\"";
    for extra in [
        // Camera lists only (acceptance 3's setting).
        vec![v, "integrator.light_samples=0"],
        // NEE lists on the device, the lobe, an environment.
        vec![v, "integrator.light_samples=48", "integrator.shading=true", "integrator.n=8"],
        vec![v, "integrator.scattering=\"all\"", "integrator.max_depth=4", "integrator.light_samples=16"],
        vec![v, "integrator.scattering=\"first\"", "integrator.max_depth=4", "integrator.light_samples=8"],
        vec![v, "integrator.optimise=false"],
        // Importance by scalar, gradient and box, and a mask.
        vec![
            v,
            "integrator.light_samples=32",
            "media.0.importance=[{ scalar = [0.3, 2.0], box = [[-1.0, -1.0, -1.0], [0.2, 1.0, 1.0]] }, \
             { gradient = [20.0, 1e9], value = 0.5 }, \
             { mask = { procedural = \"cloud\", resolution = 16, seed = 9 }, mask_threshold = 0.2, value = 0.25 }]",
        ],
        // Pre-interpolative importance (Figs. 3, 11), box-filtered, nearest.
        vec![
            v,
            "integrator.light_samples=32",
            "media.0.importance_pre={ filter = \"nearest\", box = true }",
        ],
    ] {
        let s = scene(&extra);
        assert_gpu_matches_cpu(&gpu, &s, 48, 0.005, &format!("{extra:?}"));
    }
}

#[test]
fn visopt_with_a_transfer_function_and_environment_matches_the_cpu() {
    let Some(mut gpu) = test_gpu() else { return };
    // NEE-list scratch for 8 rows of 24 lists: two bands of rows.
    gpu.scratch_budget = 20 * 8 * 24 * 16;
    let s = scene(&[
        "integrator.type=\"visopt\"",
        "integrator.light_samples=24",
        "media.0.transfer={ opacity = [[0.0, 0.0], [0.2, 0.0], [0.3, 1.0], [1.0, 0.5]], \
         color = [[0.0, 1.0, 0.3, 0.2], [1.0, 0.4, 0.9, 0.9]] }",
        "lights=[{ type = \"constant\", radiance = [0.3, 0.4, 0.5] }, \
         { type = \"point\", position = [1.5, 1.5, 1.0], intensity = [40.0, 40.0, 40.0] }]",
    ]);
    assert_gpu_matches_cpu(&gpu, &s, 48, 0.005, "transfer function + environment");
}

/// Ament's march is deterministic without jitter: with pixel centres the
/// GPU must give the CPU's pixel values up to f32 rounding.
#[test]
fn ament_matches_the_cpu_pixel_for_pixel() {
    let Some(gpu) = test_gpu() else { return };
    let a = "integrator.type=\"ament\"";
    let centre = "render.pixel_jitter=false";
    for extra in [
        vec![a, centre, "integrator.step=0.1"],
        vec![
            a,
            centre,
            "integrator.step=0.1",
            "integrator.form=\"printed\"",
            "integrator.q=0.5",
            "integrator.r=0.2",
        ],
        vec![
            a,
            centre,
            "integrator.step=0.1",
            "integrator.optimise=false",
        ],
        vec![
            a,
            centre,
            "integrator.step=0.1",
            "integrator.shading=true",
            "integrator.n=8",
        ],
    ] {
        let s = scene(&extra);
        let opts = RenderOptions::new(1, 1);
        let cpu = render(&s, &opts, &Progress::default()).film.mean();
        let g = gpu_render::render(&gpu, &s, &opts, &Progress::default()).unwrap();
        let gm = g.film.mean();
        let mean: f32 = cpu.iter().map(|p| p[0]).sum::<f32>() / cpu.len() as f32;
        assert!(mean > 0.005, "{extra:?}: the scene must be lit");
        let worst = cpu
            .iter()
            .zip(&gm)
            .flat_map(|(c, g)| (0..3).map(move |k| (c[k] - g[k]).abs() / c[k].max(0.05 * mean)))
            .fold(0.0f32, f32::max);
        eprintln!("{extra:?}: worst relative difference {worst:.2e}");
        assert!(worst < 2e-3, "{extra:?}: worst relative difference {worst}");
    }
}

/// With a jittered start the march is a Monte Carlo estimate: z-test.
#[test]
fn jittered_ament_matches_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let s = scene(&[
        "integrator.type=\"ament\"",
        "integrator.step=0.1",
        "integrator.jitter=true",
    ]);
    assert_gpu_matches_cpu(&gpu, &s, 32, 0.005, "ament jitter");
}

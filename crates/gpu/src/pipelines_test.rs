//! The pipeline cache (crate::pipelines): one build per kernel and device.

use crate::{render::render, test_gpu, Gpu};
use fogbank_render::{parse_scene, Progress, RenderOptions, Scene};
use std::path::Path;

fn scene(resolution: u32, estimator: &str) -> Scene {
    let text = format!(
        "[camera]\nwidth = 8\nheight = 6\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = {resolution}, seed = 5 }}\n\
         sigma_t_scale = 8.0\n[integrator]\ntype = \"transmittance\"\nestimator = \"{estimator}\"\n"
    );
    Scene::build(parse_scene(&text, "test", &[]).unwrap(), Path::new(".")).unwrap()
}

fn built_by(gpu: &Gpu, s: &Scene) -> u64 {
    let before = gpu.pipelines_built();
    let opts = RenderOptions::new(2, 1);
    render(gpu, s, &opts, &Progress::default()).unwrap();
    gpu.pipelines_built() - before
}

/// A render builds its kernel's two pipelines (samples, merge) once per
/// device: again for another estimator, not for another scene with the
/// same kernel, nor for a clone of the device handle.
#[test]
fn pipelines_are_built_once_per_kernel_and_device() {
    if test_gpu().is_none() {
        return;
    }
    // Its own device: the shared one's count moves with other tests.
    let gpu = Gpu::new().unwrap();
    assert_eq!(built_by(&gpu, &scene(16, "ratio_tracking")), 2);
    assert_eq!(built_by(&gpu, &scene(16, "ratio_tracking")), 0);
    assert_eq!(built_by(&gpu.clone(), &scene(24, "ratio_tracking")), 0);
    assert_eq!(built_by(&gpu, &scene(16, "track_length")), 2);
}

//! `test_tint` on the GPU (test-only; the CPU's is
//! `fogbank_render::integrators::test_tint`): `test_tint.wgsl` over the
//! frame alone, the tint in the frame's background. With its CPU folder and
//! the two registry lines, all that adding an integrator on both backends
//! takes.

use super::kernel::KernelParams;
use super::plugin::GpuIntegrator;
use crate::shaders;
use crate::GpuError;
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::integrators::test_tint::{TestTint, TestTintParams};
use fogbank_render::Scene;

const KERNEL: &str = include_str!("test_tint.wgsl");

pub struct TestTintPort;

impl GpuIntegrator for TestTintPort {
    type Cpu = TestTint;
    const NAME: &'static str = TestTintParams::NAME;

    fn kernel(cpu: &TestTint, _scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
        Ok(KernelParams {
            scatter: false,
            background: cpu.tint,
            max_depth: 0,
            rr_depth: 0,
            ..k
        })
    }

    fn source(_k: &KernelParams) -> String {
        shaders::per_sample_kernel(KERNEL)
    }
}

#[cfg(test)]
mod tests {
    use fogbank_render::{parse_scene, Progress, RenderOptions, Scene};
    use std::path::Path;

    /// The same image on both backends: both draw the same random streams,
    /// so pixels agree to float rounding.
    #[test]
    fn it_renders_as_on_the_cpu() {
        let Some(gpu) = crate::test_gpu() else {
            return;
        };
        let o: Vec<String> = [
            "integrator.type=test_tint",
            "camera.width=16",
            "camera.height=12",
            "media.0.density.resolution=16",
        ]
        .map(String::from)
        .to_vec();
        let desc = parse_scene(fogbank_render::DEFAULT_SCENE, "built-in", &o).unwrap();
        let scene = Scene::build(desc, Path::new(".")).unwrap();
        let opts = RenderOptions::new(8, 3);
        let g = crate::render::render(&gpu, &scene, &opts, &Progress::default()).unwrap().film;
        let c = fogbank_render::render(&scene, &opts, &Progress::default()).film;
        assert_eq!(g.nan_samples + g.inf_samples, 0);
        let (gm, cm) = (g.mean(), c.mean());
        let close = (gm.iter().zip(&cm))
            .filter(|(a, b)| (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-3 * b[k].abs().max(1.0)))
            .count();
        assert!(close * 10 >= gm.len() * 9, "{close} of {} pixels agree", gm.len());
        // The ramp: the right half is brighter than the left where both
        // see no medium, and blue is a quarter of red.
        assert!(gm.iter().all(|p| (p[2] - p[0] / 4.0).abs() <= 1e-5));
        assert!(gm[15][0] > gm[0][0], "{:?} {:?}", gm[15], gm[0]);
    }
}

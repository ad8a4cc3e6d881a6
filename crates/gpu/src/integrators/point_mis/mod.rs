//! `point_mis` on the GPU: `point_mis.wgsl`, its strategy a pipeline
//! constant; shapes are opaque occluders (`wgsl/occluders.wgsl`).

use super::kernel::{surfaces_flag, KernelParams};
use super::shared::occluder_constants;
use super::plugin::GpuIntegrator;
use crate::contract::strategy_id;
use crate::shaders;
use crate::GpuError;
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::integrators::point_mis::{PointMis, PointMisParams};
use fogbank_render::lights::sample::LightSampler;
use fogbank_render::Scene;
use std::borrow::Cow;

const KERNEL: &str = include_str!("point_mis.wgsl");

pub struct PointMisPort;

/// Its source: the scattering prelude, the occluders, the kernel.
pub(crate) fn source() -> String {
    shaders::occluding_kernel(KERNEL)
}

impl GpuIntegrator for PointMisPort {
    type Cpu = PointMis;
    const NAME: &'static str = PointMisParams::NAME;

    fn kernel(cpu: &PointMis, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
        Ok(KernelParams {
            strategy: strategy_id(cpu.strategy),
            mis_samples: cpu.mis_samples,
            flags: surfaces_flag(scene),
            ..k
        })
    }

    fn source(_k: &KernelParams) -> String {
        source()
    }

    fn constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
        let mut c = vec![("STRATEGY", k.strategy as f64)];
        c.extend(occluder_constants(k));
        c
    }

    fn light_sampler<'s>(cpu: &'s PointMis, _scene: &Scene) -> Cow<'s, LightSampler> {
        Cow::Borrowed(&cpu.lights)
    }
}

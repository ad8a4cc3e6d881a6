//! `volpath` on the GPU: the scatter kernel (`wgsl/scatter_kernel.wgsl`)
//! with roulette, its distance sampler, and Hansen 2025's ray marching and
//! pins (group 3: the pin grids gathered on the device, [`crate::pins`]).

use super::kernel::{surfaces_flag, KernelParams};
use super::shared::{scatter_constants, scatter_group3};
use super::plugin::{GpuIntegrator, Group3};
use crate::contract::{
    sampler_id, INTEGRATOR_LIGHT_ONLY, INTEGRATOR_RAY_MARCHING, INTEGRATOR_UNQUANTISED,
};
use crate::scene_buffers::SceneBuffers;
use crate::shaders;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::integrators::shared::pin_params::Tracking;
use fogbank_render::integrators::volpath::{VolPath, VolPathParams};
use fogbank_render::lights::sample::LightSampler;
use fogbank_render::Scene;
use std::borrow::Cow;

pub struct VolPathPort;

impl GpuIntegrator for VolPathPort {
    type Cpu = VolPath;
    const NAME: &'static str = VolPathParams::NAME;
    const CHROMATIC: bool = true;

    fn kernel(cpu: &VolPath, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
        Ok(KernelParams {
            flags: flags(cpu) | surfaces_flag(scene),
            max_depth: cpu.max_depth,
            rr_depth: cpu.rr_depth,
            sampler: sampler_id(cpu.distance),
            pins: cpu.pins.clone(),
            ..k
        })
    }

    fn source(_k: &KernelParams) -> String {
        shaders::scatter_kernel()
    }

    fn constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
        scatter_constants(k)
    }

    fn light_sampler<'s>(cpu: &'s VolPath, _scene: &Scene) -> Cow<'s, LightSampler> {
        Cow::Borrowed(&cpu.lights)
    }

    fn group3(
        _cpu: &VolPath,
        gpu: &Gpu,
        scene: &Scene,
        k: &KernelParams,
        media: &SceneBuffers,
    ) -> Result<Option<Group3>, GpuError> {
        scatter_group3(gpu, scene, k, media)
    }
}

/// `INTEGRATOR_*` bits of a `volpath`.
fn flags(v: &VolPath) -> u32 {
    let mut f = 0;
    if v.light_only {
        f |= INTEGRATOR_LIGHT_ONLY;
    }
    if v.pins.tracking() == Tracking::RayMarching {
        f |= INTEGRATOR_RAY_MARCHING;
    }
    if v.pins.grid.unquantised {
        f |= INTEGRATOR_UNQUANTISED;
    }
    f
}

//! `direct` on the GPU: single scattering in the scatter kernel
//! (`wgsl/scatter_kernel.wgsl`, one vertex), its distance sampler a
//! pipeline constant.

use super::kernel::{surfaces_flag, KernelParams};
use super::shared::{scatter_constants, scatter_group3};
use super::plugin::{GpuIntegrator, Group3};
use crate::contract::sampler_id;
use crate::scene_buffers::SceneBuffers;
use crate::shaders;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::direct::{Direct, DirectParams};
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::lights::sample::LightSampler;
use fogbank_render::Scene;
use std::borrow::Cow;

pub struct DirectPort;

impl GpuIntegrator for DirectPort {
    type Cpu = Direct;
    const NAME: &'static str = DirectParams::NAME;
    const CHROMATIC: bool = true;

    fn kernel(cpu: &Direct, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
        Ok(KernelParams {
            flags: surfaces_flag(scene),
            sampler: sampler_id(cpu.distance),
            ..k
        })
    }

    fn source(_k: &KernelParams) -> String {
        shaders::scatter_kernel()
    }

    fn constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
        scatter_constants(k)
    }

    fn light_sampler<'s>(cpu: &'s Direct, _scene: &Scene) -> Cow<'s, LightSampler> {
        Cow::Borrowed(&cpu.lights)
    }

    fn group3(
        _cpu: &Direct,
        gpu: &Gpu,
        scene: &Scene,
        k: &KernelParams,
        media: &SceneBuffers,
    ) -> Result<Option<Group3>, GpuError> {
        scatter_group3(gpu, scene, k, media)
    }
}

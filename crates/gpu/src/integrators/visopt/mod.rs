//! `visopt` on the GPU (Lerzer and Dachsbacher 2025 §5.4): importance rules,
//! the camera lists built and frozen on the CPU, the optimised view
//! (`visopt.wgsl`, `params.wgsl`, `importance.wgsl`, `segments.wgsl`);
//! group 3 is [`buffers::VisOptBuffers`], which `ament` shares. Shapes are
//! opaque occluders. Its NEE lists are per-pixel scratch: one chunk of
//! samples a dispatch, in bands of rows that fit the scratch budget.

pub(crate) mod buffers;
pub(crate) mod source;

use super::kernel::{surfaces_flag, KernelParams};
use super::shared::occluder_constants;
use super::plugin::{GpuIntegrator, Group3};
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
pub use buffers::scratch;
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::integrators::visopt::{VisOpt, VisOptParams};
use fogbank_render::lights::sample::LightSampler;
use fogbank_render::world::field::Field;
use fogbank_render::Scene;
use std::borrow::Cow;

pub struct VisOptPort;

impl GpuIntegrator for VisOptPort {
    type Cpu = VisOpt;
    const NAME: &'static str = VisOptParams::NAME;
    const CHUNKS_TOGETHER: bool = false;

    fn kernel(_cpu: &VisOpt, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
        Ok(KernelParams {
            flags: surfaces_flag(scene),
            ..k
        })
    }

    fn source(_k: &KernelParams) -> String {
        source::source()
    }

    fn constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
        occluder_constants(k)
    }

    fn light_sampler<'s>(cpu: &'s VisOpt, _scene: &Scene) -> Cow<'s, LightSampler> {
        Cow::Borrowed(&cpu.lights)
    }

    fn fields<'s>(_cpu: &'s VisOpt, scene: &'s Scene) -> Vec<&'s Field> {
        buffers::importance_fields(scene)
    }

    fn group3(
        _cpu: &VisOpt,
        gpu: &Gpu,
        scene: &Scene,
        _k: &KernelParams,
        media: &SceneBuffers,
    ) -> Result<Option<Group3>, GpuError> {
        buffers::group3(gpu, scene, media)
    }
}

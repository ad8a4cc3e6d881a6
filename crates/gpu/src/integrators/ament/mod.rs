//! `ament` on the GPU (Lerzer and Dachsbacher 2025's ray-marched
//! baseline): `ament.wgsl` over `visopt`'s parameters, importance rules and
//! group 3 ([`super::visopt::buffers`]); it marches to every light and
//! picks none. Shapes are opaque occluders.

use super::kernel::{surfaces_flag, KernelParams};
use super::shared::occluder_constants;
use super::visopt::buffers;
use super::visopt::source::{IMPORTANCE, PARAMS};
use super::plugin::{GpuIntegrator, Group3};
use crate::scene_buffers::SceneBuffers;
use crate::shaders;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::ament::{Ament, AmentParams};
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::world::field::Field;
use fogbank_render::Scene;

const KERNEL: &str = include_str!("ament.wgsl");

pub struct AmentPort;

/// Its source: the scattering prelude, the occluders, the importance rules
/// and the march.
pub(crate) fn source() -> String {
    shaders::occluding_kernel(&[PARAMS, IMPORTANCE, KERNEL].join("\n"))
}

impl GpuIntegrator for AmentPort {
    type Cpu = Ament;
    const NAME: &'static str = AmentParams::NAME;

    fn kernel(_cpu: &Ament, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
        Ok(KernelParams {
            flags: surfaces_flag(scene),
            ..k
        })
    }

    fn source(_k: &KernelParams) -> String {
        source()
    }

    fn constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
        occluder_constants(k)
    }

    fn fields<'s>(_cpu: &'s Ament, scene: &'s Scene) -> Vec<&'s Field> {
        buffers::importance_fields(scene)
    }

    fn group3(
        _cpu: &Ament,
        gpu: &Gpu,
        scene: &Scene,
        _k: &KernelParams,
        media: &SceneBuffers,
    ) -> Result<Option<Group3>, GpuError> {
        buffers::group3(gpu, scene, media)
    }
}

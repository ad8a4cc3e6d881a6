//! What a per-sample kernel asks of the render loop: the estimator, the
//! frame options and the choices its pipeline constants carry. Each port
//! fills in its own ([`super::plugin::GpuIntegrator::kernel`]).

use crate::contract::{GpuEstimator, INTEGRATOR_SURFACES};
use fogbank_render::integrators::shared::pin_params::PinParams;
use fogbank_render::Scene;

/// What the integrator asks of the kernels.
pub(crate) struct KernelParams {
    /// Needs bind group 2 (lights, environment, shading).
    pub(crate) scatter: bool,
    /// The transmittance estimator's `EST_*` id and frame options.
    pub(crate) est: GpuEstimator,
    pub(crate) background: glam::Vec3,
    pub(crate) max_depth: u32,
    pub(crate) rr_depth: u32,
    /// The distance sampler's `SAMPLER_*` id (`direct`, `volpath`).
    pub(crate) sampler: u32,
    /// `point_mis`'s `STRATEGY_*` id.
    pub(crate) strategy: u32,
    pub(crate) mis_samples: u32,
    /// `INTEGRATOR_*` bits.
    pub(crate) flags: u32,
    /// `volpath`'s Hansen 2025 keys (`pins`, `tracking`, `march_step`,
    /// `pin_grid`); the default is plain `volpath`.
    pub(crate) pins: PinParams,
    /// Emitting triangles are picked through a light BVH (`LIGHT_BVH`).
    pub(crate) light_bvh: bool,
}

impl KernelParams {
    /// A scattering kernel with estimator `est`: one vertex, no roulette,
    /// no distance sampler, no flags.
    pub(crate) fn new(est: GpuEstimator, light_bvh: bool) -> KernelParams {
        KernelParams {
            scatter: true,
            est,
            background: glam::Vec3::ZERO,
            max_depth: 1,
            rr_depth: u32::MAX,
            sampler: 0,
            strategy: 0,
            mis_samples: 0,
            flags: 0,
            pins: PinParams::default(),
            light_bvh,
        }
    }
}

/// `INTEGRATOR_SURFACES` when the scene has shapes (compiled out without).
pub(crate) fn surfaces_flag(scene: &Scene) -> u32 {
    if scene.world.surfaces.is_some() {
        INTEGRATOR_SURFACES
    } else {
        0
    }
}

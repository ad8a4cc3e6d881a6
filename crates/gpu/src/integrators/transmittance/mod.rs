//! `transmittance` on the GPU: `transmittance.wgsl`, the transmittance of
//! each camera ray through all media times the background; through
//! surfaces or chromatic media, the scatter kernel's shadow walk, as the
//! CPU's `transmittance::sample` takes its shadow transmittance there.

use super::kernel::{surfaces_flag, KernelParams};
use super::shared::{scatter_constants, scatter_group3};
use super::plugin::{GpuIntegrator, Group3};
use crate::contract::INTEGRATOR_TRANSMITTANCE;
use crate::scene_buffers::SceneBuffers;
use crate::shaders;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::transmittance::{Transmittance, TransmittanceParams};
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::Scene;

const KERNEL: &str = include_str!("transmittance.wgsl");

pub struct TransmittancePort;

/// The per-camera-ray kernel (no scattering, no lights).
pub(crate) fn source() -> String {
    shaders::per_sample_kernel(KERNEL)
}

impl GpuIntegrator for TransmittancePort {
    type Cpu = Transmittance;
    const NAME: &'static str = TransmittanceParams::NAME;
    const CHROMATIC: bool = true;

    fn kernel(cpu: &Transmittance, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
        let surfaces = surfaces_flag(scene);
        let chromatic = scene.media.iter().any(|m| m.chroma.is_some());
        Ok(if surfaces != 0 || chromatic {
            KernelParams {
                flags: INTEGRATOR_TRANSMITTANCE | surfaces,
                background: cpu.background,
                max_depth: 0,
                ..k
            }
        } else {
            KernelParams {
                scatter: false,
                background: cpu.background,
                max_depth: 0,
                rr_depth: 0,
                ..k
            }
        })
    }

    fn source(k: &KernelParams) -> String {
        if k.scatter {
            shaders::scatter_kernel()
        } else {
            source()
        }
    }

    fn constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
        if k.scatter {
            scatter_constants(k)
        } else {
            Vec::new()
        }
    }

    fn group3(
        _cpu: &Transmittance,
        gpu: &Gpu,
        scene: &Scene,
        k: &KernelParams,
        media: &SceneBuffers,
    ) -> Result<Option<Group3>, GpuError> {
        if k.scatter {
            scatter_group3(gpu, scene, k, media)
        } else {
            Ok(None)
        }
    }
}

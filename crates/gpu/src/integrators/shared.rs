//! What several ports share: the scatter kernel (`wgsl/scatter_kernel.wgsl`:
//! `direct`, `volpath`, and `transmittance` through surfaces or chromatic
//! media) with its pipeline constants and its group 3 (Hansen 2025's pin
//! grids, one absent record when pins are off), and the constants of the
//! kernels that see shapes as opaque occluders (`point_mis`, `visopt`,
//! `ament`).

use super::kernel::KernelParams;
use super::plugin::Group3;
use crate::contract::{pin_mode_id, INTEGRATOR_SURFACES};
use crate::pins::PinBuffers;
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::shared::pin_params::PinMode;
use fogbank_render::Scene;

/// The scatter kernel's pipeline constants: the distance sampler, the pin
/// mode, the integrator flags and the light BVH.
pub(crate) fn scatter_constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
    vec![
        ("SAMPLER", k.sampler as f64),
        ("PIN_MODE", pin_mode_id(k.pins.mode) as f64),
        ("INTEGRATOR_FLAGS", k.flags as f64),
        ("LIGHT_BVH", k.light_bvh as u32 as f64),
    ]
}

/// The scatter kernel's group 3: `k`'s pin grids gathered on the device
/// (one absent record when pins are off).
pub(crate) fn scatter_group3(
    gpu: &Gpu,
    scene: &Scene,
    k: &KernelParams,
    media: &SceneBuffers,
) -> Result<Option<Group3>, GpuError> {
    let on = k.pins.mode != PinMode::Off;
    let p = PinBuffers::build(gpu, scene, media, on.then_some(&k.pins))?;
    Ok(Some(Group3 {
        layout: p.layout,
        bind_group: p.bind_group,
        bytes: p.bytes,
        band_rows: None,
        stream: p.stream,
    }))
}

/// The constants of a kernel that sees shapes as opaque occluders
/// (occluders.wgsl's `OCCLUDERS`: the scene has shapes) and may pick
/// emitting triangles through the light BVH.
pub(crate) fn occluder_constants(k: &KernelParams) -> Vec<(&'static str, f64)> {
    let occluders = (k.flags & INTEGRATOR_SURFACES) != 0;
    vec![
        ("OCCLUDERS", occluders as u32 as f64),
        ("LIGHT_BVH", k.light_bvh as u32 as f64),
    ]
}

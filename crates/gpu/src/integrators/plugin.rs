//! What an integrator's GPU port provides, in its own folder: what its
//! kernel asks ([`KernelParams`]), its WGSL and pipeline constants, its
//! light sampler, the fields and bind group 3 it uploads, or passes of its
//! own. `integrators/mod.rs` registers each port in one line of its
//! `gpu_integrators!` list, which generates the dispatch over them.

use super::kernel::KernelParams;
use crate::accumulation::{GpuRender, Observer};
use crate::pin_stream::PinStreamPass;
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
use fogbank_render::lights::sample::LightSampler;
use fogbank_render::world::field::Field;
use fogbank_render::{Progress, RenderOptions, Scene};
use std::borrow::Cow;

/// An integrator's GPU port. Associated functions over the CPU's built
/// integrator (`Cpu`, the payload of its `IntegratorKind` variant), so the
/// generated dispatch is a `match`, as on the CPU.
pub(crate) trait GpuIntegrator {
    /// The CPU's built integrator this ports.
    type Cpu;
    /// Its `integrator.type` (the CPU's `IntegratorParams::NAME`).
    const NAME: &'static str;
    /// It renders chromatic extinction (`sigma_t_scale = [r, g, b]`).
    const CHROMATIC: bool = false;
    /// Its chunks of samples run side by side in one dispatch; false where
    /// the kernel keeps per-pixel scratch (one chunk a dispatch).
    const CHUNKS_TOGETHER: bool = true;

    /// Its kernel runs passes of its own ([`GpuIntegrator::render_passes`])
    /// instead of the progressive per-sample loop.
    const OWN_PASSES: bool = false;

    /// What it asks of its kernel, from `k` (the estimator, one scattering
    /// vertex, no roulette, sampler or flags).
    fn kernel(cpu: &Self::Cpu, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError>;

    /// Its WGSL, with entry points `main` and `merge` (`accumulate.wgsl`).
    fn source(k: &KernelParams) -> String;

    /// Its pipeline constants beside `ESTIMATOR`: the choices its hot loops
    /// branch on, so that the driver compiles the branches not taken out.
    fn constants(_k: &KernelParams) -> Vec<(&'static str, f64)> {
        Vec::new()
    }

    /// The light sampler its kernel mirrors (bind group 2). By default the
    /// scene's, for a kernel that picks no light: its bindings still hold
    /// the scene's lights.
    fn light_sampler<'s>(_cpu: &'s Self::Cpu, scene: &Scene) -> Cow<'s, LightSampler> {
        Cow::Owned(scene_lights(scene))
    }

    /// Fields its kernel reads as property records of the media buffer,
    /// after the media's own ([`SceneBuffers::field_first`]).
    fn fields<'s>(_cpu: &'s Self::Cpu, _scene: &'s Scene) -> Vec<&'s Field> {
        Vec::new()
    }

    /// Its bind group 3, if it has one.
    fn group3(
        _cpu: &Self::Cpu,
        _gpu: &Gpu,
        _scene: &Scene,
        _k: &KernelParams,
        _media: &SceneBuffers,
    ) -> Result<Option<Group3>, GpuError> {
        Ok(None)
    }

    /// The render of a port with [`GpuIntegrator::OWN_PASSES`].
    fn render_passes(
        _cpu: &Self::Cpu,
        _gpu: &Gpu,
        _scene: &Scene,
        _opts: &RenderOptions,
        _progress: &Progress,
        _after: Option<Observer<'_>>,
    ) -> Result<GpuRender, GpuError> {
        Err(GpuError(format!(
            "integrator `{}` runs the per-sample kernel, no passes of its own",
            Self::NAME
        )))
    }
}

/// An integrator's bind group 3 and what the render loop needs of it.
pub(crate) struct Group3 {
    pub(crate) layout: wgpu::BindGroupLayout,
    pub(crate) bind_group: wgpu::BindGroup,
    /// Bytes uploaded or allocated for it.
    pub(crate) bytes: u64,
    /// Rows per dispatch when it holds per-pixel scratch.
    pub(crate) band_rows: Option<u32>,
    /// Hansen 2025's pin stream, which changes the grids before each
    /// sample index.
    pub(crate) stream: Option<PinStreamPass>,
}

/// A sampler over the scene's lights with its selection, for a kernel that
/// picks none (its bindings still hold the scene's lights).
pub(crate) fn scene_lights(scene: &Scene) -> LightSampler {
    LightSampler::new(
        &scene.world.lights,
        scene.world.radius(),
        scene.world.light_selection,
    )
}

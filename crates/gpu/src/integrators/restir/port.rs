//! `restir`'s port: it runs its own passes ([`super::sequences::render`]),
//! not a per-sample kernel.

use super::sequences::render;
use crate::accumulation::{GpuRender, Observer};
use crate::integrators::kernel::KernelParams;
use crate::integrators::plugin::GpuIntegrator;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::plugin::IntegratorParams;
use fogbank_render::integrators::restir::{Restir, RestirParams};
use fogbank_render::lights::sample::LightSampler;
use fogbank_render::{Progress, RenderOptions, Scene};
use std::borrow::Cow;

pub struct RestirPort;

impl GpuIntegrator for RestirPort {
    type Cpu = Restir;
    const NAME: &'static str = RestirParams::NAME;
    const OWN_PASSES: bool = true;

    fn kernel(_cpu: &Restir, _scene: &Scene, _k: KernelParams) -> Result<KernelParams, GpuError> {
        Err(GpuError(
            "integrator `restir` runs its own passes, not a per-sample kernel"
                .into(),
        ))
    }

    fn source(_k: &KernelParams) -> String {
        super::source::source()
    }

    fn light_sampler<'s>(cpu: &'s Restir, _scene: &Scene) -> Cow<'s, LightSampler> {
        Cow::Borrowed(&cpu.lights)
    }

    fn render_passes(
        _cpu: &Restir,
        gpu: &Gpu,
        scene: &Scene,
        opts: &RenderOptions,
        progress: &Progress,
        after: Option<Observer<'_>>,
    ) -> Result<GpuRender, GpuError> {
        render(gpu, scene, opts, progress, after)
    }
}

//! The GPU's integrators, one folder each (its WGSL and one `mod.rs`
//! implementing [`GpuIntegrator`]: what its kernel asks, its source and
//! pipeline constants, its light sampler, its bind group 3, its dispatch),
//! registered in one line of the `gpu_integrators!` list below — as the
//! CPU's are in `fogbank_render::integrators`' `integrators!`. The list
//! generates [`Port`], the scene's integrator paired with its GPU port, and
//! every dispatch over it. An integrator without a line here is refused
//! with "has no GPU kernel".
//!
//! Beside the ports: [`plugin`] (the trait), [`kernel`] (what a kernel asks
//! of the render loop), [`shared`] (the scatter kernel of `transmittance`
//! through surfaces, `direct` and `volpath`; the occluders of `point_mis`,
//! `visopt` and `ament`).

pub(crate) mod kernel;
pub(crate) mod plugin;
pub(crate) mod shared;

use crate::accumulation::{GpuRender, Observer};
use crate::contract::{gpu_estimator, INTEGRATOR_CHROMATIC};
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::lights::sample::LightSampler;
use fogbank_render::world::field::Field;
use fogbank_render::{Progress, RenderOptions, Scene};
use kernel::KernelParams;
use plugin::{GpuIntegrator, Group3};
use std::borrow::Cow;

/// The integrators with a GPU port, one line each: the CPU's
/// `IntegratorKind` variant, the port's folder (declared here) and its
/// type. Generates [`Port`] and every dispatch over it.
macro_rules! gpu_integrators {
    ($($(#[$meta:meta])* $variant:ident => $module:ident::$name:ident,)*) => {
        $($(#[$meta])* pub mod $module;)*
        gpu_integrators!(@ports $($(#[$meta])* $variant => $module::$name,)*);
    };
    (@ports $($(#[$meta:meta])* $variant:ident => $port:ty,)*) => {
        /// The scene's integrator with its GPU port.
        #[derive(Clone, Copy)]
        pub(crate) enum Port<'s> {
            $($(#[$meta])* $variant(&'s <$port as GpuIntegrator>::Cpu),)*
        }

        impl<'s> Port<'s> {
            /// The port of `kind`, if it has one.
            pub(crate) fn of(kind: &'s IntegratorKind) -> Option<Port<'s>> {
                #[allow(unreachable_patterns)]
                match kind {
                    $($(#[$meta])* IntegratorKind::$variant(cpu) => Some(Port::$variant(cpu)),)*
                    _ => None,
                }
            }

            /// The ported integrators that render chromatic extinction.
            pub(crate) fn chromatic_names() -> Vec<&'static str> {
                let mut v = Vec::new();
                $($(#[$meta])* if <$port as GpuIntegrator>::CHROMATIC {
                    v.push(<$port as GpuIntegrator>::NAME);
                })*
                v
            }

            pub(crate) fn chromatic(self) -> bool {
                match self {
                    $($(#[$meta])* Port::$variant(_) => <$port as GpuIntegrator>::CHROMATIC,)*
                }
            }

            pub(crate) fn chunks_together(self) -> bool {
                match self {
                    $($(#[$meta])* Port::$variant(_) => <$port as GpuIntegrator>::CHUNKS_TOGETHER,)*
                }
            }

            pub(crate) fn own_passes(self) -> bool {
                match self {
                    $($(#[$meta])* Port::$variant(_) => <$port as GpuIntegrator>::OWN_PASSES,)*
                }
            }

            pub(crate) fn kernel(self, scene: &Scene, k: KernelParams) -> Result<KernelParams, GpuError> {
                match self {
                    $($(#[$meta])* Port::$variant(cpu) => <$port as GpuIntegrator>::kernel(cpu, scene, k),)*
                }
            }

            pub(crate) fn source(self, k: &KernelParams) -> String {
                match self {
                    $($(#[$meta])* Port::$variant(_) => <$port as GpuIntegrator>::source(k),)*
                }
            }

            pub(crate) fn constants(self, k: &KernelParams) -> Vec<(&'static str, f64)> {
                match self {
                    $($(#[$meta])* Port::$variant(_) => <$port as GpuIntegrator>::constants(k),)*
                }
            }

            pub(crate) fn light_sampler(self, scene: &Scene) -> Cow<'s, LightSampler> {
                match self {
                    $($(#[$meta])* Port::$variant(cpu) => <$port as GpuIntegrator>::light_sampler(cpu, scene),)*
                }
            }

            pub(crate) fn fields(self, scene: &'s Scene) -> Vec<&'s Field> {
                match self {
                    $($(#[$meta])* Port::$variant(cpu) => <$port as GpuIntegrator>::fields(cpu, scene),)*
                }
            }

            pub(crate) fn group3(
                self,
                gpu: &Gpu,
                scene: &Scene,
                k: &KernelParams,
                media: &SceneBuffers,
            ) -> Result<Option<Group3>, GpuError> {
                match self {
                    $($(#[$meta])* Port::$variant(cpu) => <$port as GpuIntegrator>::group3(cpu, gpu, scene, k, media),)*
                }
            }

            pub(crate) fn render_passes(
                self,
                gpu: &Gpu,
                scene: &Scene,
                opts: &RenderOptions,
                progress: &Progress,
                after: Option<Observer<'_>>,
            ) -> Result<GpuRender, GpuError> {
                match self {
                    $($(#[$meta])* Port::$variant(cpu) => <$port as GpuIntegrator>::render_passes(cpu, gpu, scene, opts, progress, after),)*
                }
            }
        }
    };
}

gpu_integrators! {
    Transmittance => transmittance::TransmittancePort,
    Direct => direct::DirectPort,
    VolPath => volpath::VolPathPort,
    PointMis => point_mis::PointMisPort,
    Restir => restir::RestirPort,
    VisOpt => visopt::VisOptPort,
    Ament => ament::AmentPort,
    #[cfg(test)]
    TestTint => test_tint::TestTintPort,
}

/// The port of `scene`'s integrator, or why it has none.
pub(crate) fn port(scene: &Scene) -> Result<Port<'_>, GpuError> {
    Port::of(&scene.integrator).ok_or_else(|| {
        GpuError(format!(
            "integrator `{}` has no GPU kernel: render it with --device cpu",
            scene.integrator.name()
        ))
    })
}

/// The light sampler the GPU mirrors for `scene`'s integrator (bind group
/// 2; an integrator without a port gets the scene's).
pub(crate) fn light_sampler(scene: &Scene) -> Cow<'_, LightSampler> {
    match Port::of(&scene.integrator) {
        Some(p) => p.light_sampler(scene),
        None => Cow::Owned(plugin::scene_lights(scene)),
    }
}

/// light_bvh.wgsl's pipeline constant `LIGHT_BVH`: whether the scene's
/// emitting triangles are picked through a light BVH (without one the
/// driver compiles the descent out).
pub(crate) fn has_light_bvh(scene: &Scene) -> bool {
    light_sampler(scene).bvh().is_some()
}

/// The kernel a scene's integrator runs: its port and what it asks.
pub(crate) struct Kernel<'s> {
    pub(crate) port: Port<'s>,
    pub(crate) params: KernelParams,
}

impl<'s> Kernel<'s> {
    /// The kernel `scene`'s integrator runs (a port with passes of its own
    /// refuses).
    pub(crate) fn of(scene: &'s Scene) -> Result<Kernel<'s>, GpuError> {
        let port = port(scene)?;
        let estimator = scene.integrator.estimator();
        let est = gpu_estimator(estimator).ok_or_else(|| {
            GpuError(format!(
                "estimator `{}` has no GPU kernel",
                estimator.name()
            ))
        })?;
        check_chromatic(scene, port)?;
        let light_bvh = port.light_sampler(scene).bvh().is_some();
        let k = port.kernel(scene, KernelParams::new(est, light_bvh))?;
        let chromatic = scene.media.iter().any(|m| m.chroma.is_some());
        let flags = k.flags | if chromatic { INTEGRATOR_CHROMATIC } else { 0 };
        Ok(Kernel {
            port,
            params: KernelParams { flags, ..k },
        })
    }

    /// Its WGSL.
    pub(crate) fn source(&self) -> String {
        self.port.source(&self.params)
    }

    /// The pipeline constants of its source: the estimator everywhere, then
    /// the integrator's.
    pub(crate) fn constants(&self) -> Vec<(&'static str, f64)> {
        let mut constants = vec![("ESTIMATOR", self.params.est.id as f64)];
        constants.extend(self.port.constants(&self.params));
        constants
    }
}

/// Refuses chromatic media where the port does not track them.
fn check_chromatic(scene: &Scene, port: Port) -> Result<(), GpuError> {
    if port.chromatic() {
        return Ok(());
    }
    match scene.media.iter().position(|m| m.chroma.is_some()) {
        Some(i) => Err(GpuError(format!(
            "media.{i}: the GPU backend renders chromatic extinction (sigma_t_scale = [r, g, b]) with {} only, not {}: render it with --device cpu",
            Port::chromatic_names().join(", "),
            scene.integrator.name()
        ))),
        None => Ok(()),
    }
}

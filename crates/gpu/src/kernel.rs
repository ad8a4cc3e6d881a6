//! Which per-sample kernel an integrator runs and what it asks of it
//! (source, bind groups, frame options): the one place the GPU's
//! integrators are registered.

use crate::contract::{gpu_estimator, sampler_id, strategy_id, GpuEstimator};
use crate::GpuError;
use fogbank_render::integrators::shared::pin_params::{PinParams, Tracking};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::Scene;

/// What the integrator asks of the kernels.
pub(crate) struct Kernel {
    pub(crate) source: KernelSource,
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

#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum KernelSource {
    Transmittance,
    Scatter,
    PointMis,
    /// Lerzer and Dachsbacher 2025: `visopt` and `ament`, group 3 their [`VisOptBuffers`].
    VisOpt,
    Ament,
}

impl Kernel {
    /// A kernel of `source` with estimator `est`: one scattering vertex, no
    /// roulette, no distance sampler, no flags.
    fn base(source: KernelSource, est: GpuEstimator) -> Kernel {
        Kernel {
            source,
            scatter: source != KernelSource::Transmittance,
            est,
            background: glam::Vec3::ZERO,
            max_depth: 1,
            rr_depth: u32::MAX,
            sampler: 0,
            strategy: 0,
            mis_samples: 0,
            flags: 0,
            pins: PinParams::default(),
            light_bvh: false,
        }
    }

    /// The kernel `scene`'s integrator runs (one description per
    /// integrator; ReSTIR runs its own passes).
    pub(crate) fn of(scene: &Scene) -> Result<Kernel, GpuError> {
        if let IntegratorKind::Restir(_) = scene.integrator {
            return Err(no_restir());
        }
        let estimator = scene.integrator.estimator();
        let est = gpu_estimator(estimator).ok_or_else(|| {
            GpuError(format!(
                "estimator `{}` has no GPU kernel",
                estimator.name()
            ))
        })?;
        check_chromatic(scene)?;
        let chromatic = scene.media.iter().any(|m| m.chroma.is_some());
        // point_mis, visopt and ament see shapes as opaque occluders
        // (occluders.wgsl; the CPU refused every other kind of shape).
        let surfaces = if scene.world.surfaces.is_some() {
            crate::contract::INTEGRATOR_SURFACES
        } else {
            0
        };
        let base = |source| Kernel::base(source, est);
        let k = match &scene.integrator {
            // With surfaces or chromatic media: the scatter kernel's shadow
            // walk, as the CPU's `transmittance::sample` takes its shadow
            // transmittance.
            IntegratorKind::Transmittance(t) if surfaces != 0 || chromatic => Kernel {
                flags: crate::contract::INTEGRATOR_TRANSMITTANCE | surfaces,
                background: t.background,
                max_depth: 0,
                ..base(KernelSource::Scatter)
            },
            IntegratorKind::Transmittance(t) => Kernel {
                background: t.background,
                max_depth: 0,
                rr_depth: 0,
                ..base(KernelSource::Transmittance)
            },
            IntegratorKind::Direct(d) => Kernel {
                flags: surfaces,
                sampler: sampler_id(d.distance),
                ..base(KernelSource::Scatter)
            },
            IntegratorKind::VolPath(v) => Kernel {
                flags: volpath_flags(v) | surfaces,
                max_depth: v.max_depth,
                rr_depth: v.rr_depth,
                sampler: sampler_id(v.distance),
                pins: v.pins.clone(),
                ..base(KernelSource::Scatter)
            },
            IntegratorKind::PointMis(p) => Kernel {
                strategy: strategy_id(p.strategy),
                mis_samples: p.mis_samples,
                flags: surfaces,
                ..base(KernelSource::PointMis)
            },
            IntegratorKind::Restir(_) => return Err(no_restir()),
            IntegratorKind::VisOpt(_) => Kernel {
                flags: surfaces,
                ..base(KernelSource::VisOpt)
            },
            IntegratorKind::Ament(_) => Kernel {
                flags: surfaces,
                ..base(KernelSource::Ament)
            },
        };
        let chromatic_flag = if chromatic {
            crate::contract::INTEGRATOR_CHROMATIC
        } else {
            0
        };
        Ok(Kernel {
            flags: k.flags | chromatic_flag,
            light_bvh: crate::lights::has_light_bvh(scene),
            ..k
        })
    }
}

/// The GPU's kernels track chromatic extinction in `volpath`, `direct` and
/// `transmittance` only.
fn check_chromatic(scene: &Scene) -> Result<(), GpuError> {
    if matches!(
        scene.integrator,
        IntegratorKind::Direct(_) | IntegratorKind::VolPath(_) | IntegratorKind::Transmittance(_)
    ) {
        return Ok(());
    }
    match scene.media.iter().position(|m| m.chroma.is_some()) {
        Some(i) => Err(GpuError(format!(
            "media.{i}: the GPU backend renders chromatic extinction (sigma_t_scale = [r, g, b]) with volpath, direct and transmittance only, not {}: render it with --device cpu",
            scene.integrator.name()
        ))),
        None => Ok(()),
    }
}

/// `INTEGRATOR_*` bits of a `volpath`.
fn volpath_flags(v: &fogbank_render::integrators::volpath::VolPath) -> u32 {
    use crate::contract::{INTEGRATOR_LIGHT_ONLY, INTEGRATOR_RAY_MARCHING, INTEGRATOR_UNQUANTISED};
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

fn no_restir() -> GpuError {
    GpuError(
        "integrator `restir` runs its own passes (crate::restir), not a per-sample kernel".into(),
    )
}

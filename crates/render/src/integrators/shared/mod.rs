//! What every integrator shares: the pixel sample and its random-stream
//! dimensions, the primary ray, the balance heuristic, the scattering
//! parameters of `direct` and `volpath`, and (in the submodules) free-flight
//! sampling, shadow transmittance, next-event estimation and escape to the
//! environment.

pub mod context;
pub mod free_flight;
pub mod next_event;
pub mod occluders;
pub mod pin_params;
pub mod pin_stream;
pub mod tracking;

use crate::error::SceneError;
use crate::params::{take_estimator, Param, ParamReader};
use crate::world::World;
use fogbank_estimators::estimator::ResidualRatioTracking;
use fogbank_estimators::Estimator;
use fogbank_math::{Ray, SampleKey, Vec3};

/// Random-stream dimensions, so each purpose has its own PCG32 stream.
pub mod dim {
    pub const CAMERA: u32 = 0;
    pub const ESTIMATOR: u32 = 1;
}

#[derive(Clone, Copy, Debug, Default)]
pub struct PixelSample {
    pub radiance: Vec3,
    pub lookups: u32,
}

/// The primary ray of a pixel sample: jittered within the pixel, or through
/// its centre when `render.pixel_jitter` is off.
pub fn primary_ray(world: &World, x: u32, y: u32, key: SampleKey) -> Ray {
    let (jx, jy) = if world.pixel_jitter {
        let mut cam = SampleKey {
            dimension: dim::CAMERA,
            ..key
        }
        .rng();
        (cam.next_f32(), cam.next_f32())
    } else {
        (0.5, 0.5)
    };
    world.camera.ray(x as f32 + jx, y as f32 + jy)
}

/// The estimator stream of a pixel sample.
pub fn estimator_rng(key: SampleKey) -> fogbank_math::Pcg32 {
    SampleKey {
        dimension: dim::ESTIMATOR,
        ..key
    }
    .rng()
}

/// Floats the balance heuristic is written for (f32 in the integrators,
/// f64 in the MIS-weight analyses).
pub trait Real:
    Copy + PartialOrd + std::ops::Add<Output = Self> + std::ops::Div<Output = Self>
{
    const ZERO: Self;
    fn finite(self) -> bool;
}

impl Real for f32 {
    const ZERO: f32 = 0.0;
    fn finite(self) -> bool {
        self.is_finite()
    }
}

impl Real for f64 {
    const ZERO: f64 = 0.0;
    fn finite(self) -> bool {
        self.is_finite()
    }
}

/// Balance-heuristic weight of strategy density `a` against `b`,
/// a / (a + b); a zero or non-finite sum weighs nothing rather than NaN.
#[inline]
pub fn balance<F: Real>(a: F, b: F) -> F {
    let d = a + b;
    if d > F::ZERO && d.finite() {
        a / d
    } else {
        F::ZERO
    }
}

/// Free-flight distance sampler, selectable by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DistanceSampler {
    DeltaTracking,
    DecompositionTracking,
    /// Exact for nearest-filtered grids; analytic media fall back to delta tracking.
    RegularTracking,
}

impl DistanceSampler {
    pub const ALL: [DistanceSampler; 3] = [
        DistanceSampler::DeltaTracking,
        DistanceSampler::DecompositionTracking,
        DistanceSampler::RegularTracking,
    ];
    pub const NAMES: &'static str = "delta_tracking, decomposition_tracking or regular_tracking";

    pub fn parse(s: &str) -> Option<Self> {
        DistanceSampler::ALL.into_iter().find(|d| d.name() == s)
    }
    pub fn name(self) -> &'static str {
        match self {
            DistanceSampler::DeltaTracking => "delta_tracking",
            DistanceSampler::DecompositionTracking => "decomposition_tracking",
            DistanceSampler::RegularTracking => "regular_tracking",
        }
    }
}

/// Parameters `direct` and `volpath` share (their module docs carry the
/// table).
pub const SCATTER_PARAMS: [Param; 3] = [
    Param {
        key: "distance_sampler",
        default: "delta_tracking",
        meaning: "free-flight sampler: `delta_tracking`, `decomposition_tracking`, `regular_tracking`",
    },
    Param {
        key: "estimator",
        default: "ratio_tracking (roulette 0.03)",
        meaning: "NEE transmittance estimator (`fogbank estimators`), with its options",
    },
    Param {
        key: "preset",
        default: "none",
        meaning: "`baseline`: decomposition tracking (unless `distance_sampler` is given) and residual ratio tracking NEE; `restir_baseline`: the same with light sampling only (no phase-sampled escape MIS) and Russian roulette by albedo, Lin et al. 2021's baseline exactly (§6, §6.1; give the medium `supervoxel = 8`)",
    },
];

/// A named configuration of the scattering integrators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// Decomposition tracking and residual ratio tracking NEE.
    Baseline,
    /// Lin et al. 2021's baseline exactly (§6, §6.1): `Baseline`, with light
    /// sampling only (no phase-sampled escape to the environment; a camera
    /// ray that escapes still sees it, Eq. 1) and Russian roulette with the
    /// vertex albedo as continue probability. The paper's super-voxels of
    /// 8³ are the medium's `supervoxel = 8`.
    RestirBaseline,
}

impl Preset {
    pub fn name(self) -> &'static str {
        match self {
            Preset::Baseline => "baseline",
            Preset::RestirBaseline => "restir_baseline",
        }
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScatterParams {
    pub distance_sampler: Option<DistanceSampler>,
    pub estimator: Estimator,
    pub preset: Option<Preset>,
}

impl ScatterParams {
    pub fn read_scatter(r: &mut ParamReader) -> Result<ScatterParams, SceneError> {
        let distance_sampler = match r.take::<String>("distance_sampler")? {
            None => None,
            Some(s) => Some(DistanceSampler::parse(&s).ok_or_else(|| {
                SceneError(format!(
                    "{}: `{s}` is not {}",
                    r.key_path("distance_sampler"),
                    DistanceSampler::NAMES
                ))
            })?),
        };
        let estimator = take_estimator(r)?;
        let preset = match r.take::<String>("preset")?.as_deref() {
            None => None,
            Some("baseline") => Some(Preset::Baseline),
            Some("restir_baseline") => Some(Preset::RestirBaseline),
            Some(other) => {
                return Err(SceneError(format!(
                    "{}: unknown preset `{other}` (available: baseline, restir_baseline)",
                    r.key_path("preset")
                )))
            }
        };
        Ok(ScatterParams {
            distance_sampler,
            estimator,
            preset,
        })
    }

    pub fn write_scatter(&self, t: &mut toml::Table) {
        if let Some(d) = self.distance_sampler {
            t.insert("distance_sampler".into(), d.name().into());
        }
        t.insert(
            "estimator".into(),
            crate::params::estimator_value(self.estimator),
        );
        if let Some(p) = self.preset {
            t.insert("preset".into(), p.name().into());
        }
    }

    /// The distance sampler and NEE estimator after the preset.
    pub fn resolved(&self) -> (DistanceSampler, Estimator) {
        if self.preset.is_some() {
            (
                self.distance_sampler
                    .unwrap_or(DistanceSampler::DecompositionTracking),
                Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette: 0.0 }),
            )
        } else {
            (
                self.distance_sampler
                    .unwrap_or(DistanceSampler::DeltaTracking),
                self.estimator,
            )
        }
    }
}

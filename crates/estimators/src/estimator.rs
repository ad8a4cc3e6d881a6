//! The estimator registry: names, descriptions, and the per-ray dispatch over
//! a medium's storage type.

use fogbank_math::{Pcg32, Ray};
use fogbank_volume::{Medium, MediumView};

/// One transmittance estimate and what it cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub transmittance: f32,
    /// Full-resolution lookups (filtered σ_t evaluations) taken.
    pub lookups: u32,
}

impl Estimate {
    pub const ONE: Estimate = Estimate {
        transmittance: 1.0,
        lookups: 0,
    };
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Estimator {
    RegularTracking,
    AnalyticTrilinear,
    TrackLength,
    RatioTracking,
}

impl Estimator {
    pub const ALL: [Estimator; 4] = [
        Estimator::RegularTracking,
        Estimator::AnalyticTrilinear,
        Estimator::TrackLength,
        Estimator::RatioTracking,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Estimator::RegularTracking => "regular_tracking",
            Estimator::AnalyticTrilinear => "analytic_trilinear",
            Estimator::TrackLength => "track_length",
            Estimator::RatioTracking => "ratio_tracking",
        }
    }

    pub fn description(self) -> &'static str {
        match self {
            Estimator::RegularTracking => {
                "exact optical depth of the nearest-filtered grid by voxel DDA"
            }
            Estimator::AnalyticTrilinear => {
                "exact optical depth of the trilinear interpolant (cubic per voxel)"
            }
            Estimator::TrackLength => "delta tracking with super-voxel majorants, returns 0 or 1",
            Estimator::RatioTracking => {
                "ratio tracking with super-voxel majorants (Novák et al. 2014)"
            }
        }
    }

    pub fn biased(self) -> bool {
        false
    }

    pub fn parse(name: &str) -> Option<Estimator> {
        Estimator::ALL.into_iter().find(|e| e.name() == name)
    }

    pub fn names() -> Vec<&'static str> {
        Estimator::ALL.iter().map(|e| e.name()).collect()
    }
}

/// Expands `body` once per storage type with `v` bound to the typed view, so
/// each estimator is monomorphised and the match happens once per ray.
macro_rules! with_view {
    ($view:expr, $v:ident => $body:expr) => {
        match $view {
            MediumView::F16($v) => $body,
            MediumView::F32($v) => $body,
            MediumView::Analytic($v) => $body,
        }
    };
}

fn exact(tau: f64, lookups: u32) -> Estimate {
    Estimate {
        transmittance: (-tau).exp() as f32,
        lookups,
    }
}

/// Transmittance of `medium` along the world-space ray over `[0, t_max]`.
pub fn transmittance(
    e: Estimator,
    medium: &Medium,
    world: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> Estimate {
    let Some((r, t0, t1)) = medium.to_index(world, 0.0, t_max) else {
        return Estimate::ONE;
    };
    let view = medium.view();
    match e {
        Estimator::RegularTracking => match view {
            MediumView::F16(v) => {
                exact_pair(crate::regular_tracking::optical_depth(&v, &r, t0, t1))
            }
            MediumView::F32(v) => {
                exact_pair(crate::regular_tracking::optical_depth(&v, &r, t0, t1))
            }
            MediumView::Analytic(a) => exact(a.field.optical_depth(&r, t0, t1) * a.scale as f64, 0),
        },
        Estimator::AnalyticTrilinear => match view {
            MediumView::F16(v) => {
                exact_pair(crate::analytic_trilinear::optical_depth(&v, &r, t0, t1))
            }
            MediumView::F32(v) => {
                exact_pair(crate::analytic_trilinear::optical_depth(&v, &r, t0, t1))
            }
            MediumView::Analytic(a) => exact(a.field.optical_depth(&r, t0, t1) * a.scale as f64, 0),
        },
        Estimator::TrackLength => {
            with_view!(view, v => crate::track_length::transmittance(&v, &r, t0, t1, rng))
        }
        Estimator::RatioTracking => {
            with_view!(view, v => crate::ratio_tracking::transmittance(&v, &r, t0, t1, rng))
        }
    }
}

fn exact_pair((tau, lookups): (f64, u32)) -> Estimate {
    exact(tau, lookups)
}

//! Peters 2025's jackknife transmittance estimator and its ablations.
//!
//! `jackknife`: Alg. 2 then Alg. 1 with variance-aware importance (Eq. 5)
//! and the super-voxel minimum as control variate, two interleaved estimates
//! X0, X1 of exactly N lookups each, combined by Eq. 4. The result may be
//! negative; it is never clamped (clamping adds bias).

use crate::optical_depth::{estimates, prepare, Importance, Jitter};
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::VolumeAccess;

/// How the CDF step F_Δ is chosen (Peters 2025 §4.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepMode {
    /// F_Δ = F / N: exactly N samples per estimate on every non-empty ray.
    FixedCount,
    /// F_Δ given in optical-depth units (Peters 2025 Fig. 8d).
    FixedStep(f32),
}

/// Peters 2025, Eq. 4: K = cos(S) exp(−X̄), X̄ = (X0 + X1)/2, S = |X0 − X1|/2.
#[inline]
pub fn jackknife_transmittance(x0: f64, x1: f64) -> f64 {
    (0.5 * (x0 - x1).abs()).cos() * (-0.5 * (x0 + x1)).exp()
}

fn f_delta(total: f64, samples: u32, mode: StepMode) -> f64 {
    match mode {
        StepMode::FixedCount => total / samples.max(1) as f64,
        StepMode::FixedStep(step) => step.max(1e-6) as f64,
    }
}

/// How each optical-depth estimate samples its segment (Peters 2025 Alg. 1,
/// Alg. 2): `samples` lookups or a fixed CDF step (§4.3), the importance
/// density (Eq. 5, or the mean of the Fig. 9 ablation) and the jitter
/// pattern (§4.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    pub samples: u32,
    pub mode: StepMode,
    pub importance: Importance,
    pub jitter: Jitter,
}

impl Sampling {
    /// The jackknife's own: N lookups per estimate, variance-aware
    /// importance (Eq. 5).
    pub fn fixed_count(samples: u32, jitter: Jitter) -> Sampling {
        Sampling {
            samples,
            mode: StepMode::FixedCount,
            importance: Importance::VarianceAware,
            jitter,
        }
    }
}

/// `out.len()` interleaved optical-depth estimates of the segment
/// `seg` (all 0 when F = 0, the segment meets no medium).
pub fn optical_depths<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    sampling: Sampling,
    rng: &mut Pcg32,
    lookups: &mut u32,
    out: &mut [f64],
) {
    out.iter_mut().for_each(|x| *x = 0.0);
    let Sampling {
        samples,
        mode,
        importance,
        jitter,
    } = sampling;
    let prep = prepare(v, seg, importance);
    if prep.total > 0.0 {
        let f_delta = f_delta(prep.total, samples, mode);
        estimates(v, &prep, f_delta, jitter, rng, lookups, out);
    }
}

/// `jackknife` (and, with `Importance::Mean`, `jackknife_mean_importance`,
/// the ablation of Peters 2025 Fig. 9).
pub fn transmittance<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    sampling: Sampling,
    rng: &mut Pcg32,
) -> Estimate {
    let (mut lookups, mut x) = (0, [0.0; 2]);
    optical_depths(v, seg, sampling, rng, &mut lookups, &mut x);
    Estimate {
        transmittance: jackknife_transmittance(x[0], x[1]) as f32,
        lookups,
    }
}

/// `jackknife_naive`: exp(−X) from one estimate of 2N samples with the same
/// machinery (Peters 2025 Fig. 8c), i.e. m = 1 at equal cost.
pub fn naive_transmittance<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    samples: u32,
    jitter: Jitter,
    rng: &mut Pcg32,
) -> Estimate {
    let (mut lookups, mut x) = (0, [0.0; 1]);
    let sampling = Sampling::fixed_count(2 * samples.max(1), jitter);
    optical_depths(v, seg, sampling, rng, &mut lookups, &mut x);
    Estimate {
        transmittance: (-x[0]).exp() as f32,
        lookups,
    }
}

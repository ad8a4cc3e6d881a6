//! Exact free-flight sampling of the trilinear field (Lin et al. 2021 Fig. 12's
//! full-resolution column; the authors invert the per-voxel cubic by regula
//! falsi): walk the dual cells summing their exact optical depths until the
//! sum reaches −ln(1 − u), then solve ∫_a^x σ_t dt = rest inside that cell,
//! a monotone quartic in x, by Newton's method safeguarded by bisection.
//! The density of the returned t is σ_t(t)·T(t) of the trilinear field, the
//! same field `analytic_trilinear` integrates; stochastic trilinear media
//! have this field as their mean.

use super::TrackedFlight;
use crate::analytic_trilinear::{dual_frame, DualCell};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{Dda, GridView, Occupied, Voxel, ZERO_TRILINEAR};

/// Newton steps before giving up on tighter brackets (bisection alone
/// reaches f64 resolution in ~60).
const MAX_STEPS: u32 = 64;

/// A free flight (its [`TrackedFlight::free_flight`]) with σ_t at the collision and the optical depth up to it:
/// the closed-form density σ_t(t)·exp(−τ(t)) of the trilinear field.
pub fn sample_tracked<T: Voxel>(
    v: &GridView<'_, T>,
    seg: &RaySegment,
    rng: &mut Pcg32,
) -> TrackedFlight {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let (shifted, n, o, d) = dual_frame(v, ray);
    // The target in units of the unscaled field (∞ for a zero scale).
    let u = -(1.0 - rng.next_f32() as f64).ln();
    let scale = v.scale as f64;
    let target = u / scale;
    let mut tau = 0.0f64;
    let mut lookups = 0;
    // Zero super-voxels hold no collision and add nothing to τ ([`Occupied`]).
    for (ta, tb) in Occupied::new(v.supervoxels, ZERO_TRILINEAR, ray, t0, t1) {
        for s in Dda::new(&shifted, 1.0, n, ta, tb) {
            let (a, b) = (s.t0 as f64, s.t1 as f64);
            if b <= a {
                continue;
            }
            lookups += 1;
            let cell = DualCell::new(v.grid, s.cell);
            let d_tau = cell.integral(o, d, a, b);
            if tau + d_tau >= target && d_tau > 0.0 {
                let t = invert(&cell, o, d, a, b, target - tau, d_tau);
                let t32 = (t as f32).clamp(s.t0, s.t1);
                return TrackedFlight {
                    t: Some(t32),
                    sigma_t: scale * cell.value(o, d, t32 as f64),
                    tau: u,
                    lookups,
                };
            }
            tau += d_tau;
        }
    }
    TrackedFlight {
        t: None,
        sigma_t: 0.0,
        tau: tau * scale,
        lookups,
    }
}

/// x in [a, b] with ∫_a^x σ = rest, given ∫_a^b σ = total ≥ rest.
fn invert(
    cell: &DualCell,
    o: glam::DVec3,
    d: glam::DVec3,
    a: f64,
    b: f64,
    rest: f64,
    total: f64,
) -> f64 {
    let (mut lo, mut hi) = (a, b);
    let mut x = a + (b - a) * (rest / total).clamp(0.0, 1.0);
    for _ in 0..MAX_STEPS {
        let f = cell.integral(o, d, a, x) - rest;
        if f == 0.0 {
            return x;
        }
        if f > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        if hi - lo <= 1e-13 * (b - a) {
            break;
        }
        let slope = cell.value(o, d, x);
        let newton = x - f / slope;
        x = if slope > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    x
}

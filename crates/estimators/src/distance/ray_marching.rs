//! Ray marching with a fixed step (Hansen 2025 §2.4–§2.5, the thesis's
//! baseline and the non-pin rays of PinMS): σ_t read at jittered points one
//! step apart (one jitter per ray), τ accumulated step by step. Free flight
//! stops in the step where τ passes −ln(1 − ξ) and solves for the distance
//! inside it with that step's σ_t; transmittance is exp(−Σ σ_t Δt). Both
//! are biased (the step's constant σ_t stands for the field); the step is
//! given in the ray parameter by the caller (the thesis: a fraction of the
//! bounding box's edge).

use super::FreeFlight;
use crate::lookup::sigma_t_at;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::VolumeAccess;

/// Longest walk, in steps: a tiny step on a long segment would otherwise
/// run away.
pub const MAX_STEPS: u32 = 1 << 20;

/// The marching grid of `seg`: step `dt` (ray parameter), clamped so the
/// walk has at most [`MAX_STEPS`] steps; per step its ends `(a, b)` and the
/// point `a + u·(b − a)` where σ_t is read (one jitter `u` per ray).
#[inline]
fn steps(seg: &RaySegment, dt: f32, u: f64) -> impl Iterator<Item = (f64, f64, f64)> {
    let (t0, t1) = (seg.t0 as f64, seg.t1 as f64);
    // The length in f32, as the GPU computes it.
    let len = (seg.t1 - seg.t0) as f64;
    let dt = (dt as f64).max(len / MAX_STEPS as f64);
    let n = if len > 0.0 && dt > 0.0 {
        ((len / dt).ceil() as u32).clamp(1, MAX_STEPS)
    } else {
        0
    };
    (0..n).map(move |j| {
        let a = t0 + j as f64 * dt;
        let b = (a + dt).min(t1);
        (a, b, a + u * (b - a))
    })
}

/// Free flight on `[t0, t1]` of the index-space `ray` with step `dt`.
pub fn sample<V: VolumeAccess>(v: &V, seg: &RaySegment, dt: f32, rng: &mut Pcg32) -> FreeFlight {
    // f32 draws, as the GPU's (WGSL has no f64).
    let target = -(1.0 - rng.next_f32() as f64).ln();
    let u = rng.next_f32() as f64;
    let mut lookups = 0;
    let mut tau = 0.0f64;
    for (a, b, t) in steps(seg, dt, u) {
        let sigma = sigma_t_at(v, seg.ray.at(t as f32), rng, &mut lookups) as f64;
        let d = sigma * (b - a);
        if tau + d >= target && sigma > 0.0 {
            let hit = a + (target - tau) / sigma;
            return FreeFlight {
                t: Some((hit as f32).clamp(a as f32, b as f32)),
                lookups,
            };
        }
        tau += d;
    }
    FreeFlight { t: None, lookups }
}

/// exp(−τ̂) of `[t0, t1]` with step `dt`: (transmittance, lookups).
pub fn transmittance<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    dt: f32,
    rng: &mut Pcg32,
) -> (f32, u32) {
    let u = rng.next_f32() as f64;
    let mut lookups = 0;
    let mut tau = 0.0f64;
    for (a, b, t) in steps(seg, dt, u) {
        tau += sigma_t_at(v, seg.ray.at(t as f32), rng, &mut lookups) as f64 * (b - a);
    }
    ((-tau).exp() as f32, lookups)
}

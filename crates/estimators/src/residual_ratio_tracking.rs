//! Residual ratio tracking (Novák et al. 2014): a per-super-voxel control
//! extinction μ_c whose transmittance is computed exactly, and ratio tracking
//! of the residual μ − μ_c with the residual majorant
//! max(μ_max − μ_c, μ_c − μ_min). Unbiased.
//!
//! Control heuristic (notes, from the volumetric ReSTIR code):
//! μ_c = min(μ_avg, max(μ_min, μ_min + Δ(2^{1/(DΔ)} − 1))), Δ = μ_max − μ_min,
//! D the super-voxel diagonal in world units.
//!
//! With a `roulette` threshold > 0 the walk plays Russian roulette on its
//! running estimate exp(−τ_c)·(residual weight) once that falls below it
//! ([`crate::roulette`]).

use crate::null_collisions::{walk, Tracking};
use crate::roulette::roulette;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{SuperVoxel, VolumeAccess};

/// The control extinction of a super-voxel with world-space diagonal `d`.
pub fn control_extinction(s: &SuperVoxel, d: f32) -> f32 {
    let delta = s.max - s.min;
    if delta <= 0.0 {
        return s.min;
    }
    let c = s.min + delta * ((1.0 / (d * delta)).exp2() - 1.0);
    s.mean.min(c.max(s.min))
}

/// Residual ratio tracking of k_c σ_t with control k_c μ_c for each
/// channel c at once (k_c ≤ 1: the residual majorant bounds every
/// |k_c (σ_t − μ_c)|); k = [1] is the estimator of one channel.
pub fn transmittance_scaled<V: VolumeAccess, const N: usize>(
    v: &V,
    seg: &RaySegment,
    rng: &mut Pcg32,
    k: [f32; N],
    threshold: f32,
) -> ([f32; N], u32) {
    let ray = &seg.ray;
    // Index units per world unit along this ray turn the super-voxel's
    // index-space diagonal into world units.
    let diagonal =
        v.supervoxels().size as f32 * 3f32.sqrt() / ray.d.length().max(f32::MIN_POSITIVE);
    let mut lookups = 0;
    let tau_c = std::cell::Cell::new(0.0f64);
    let mut ratio = [1.0f32; N];
    let rate = |s: &SuperVoxel, len: f32| {
        if s.max <= 0.0 {
            return (0.0, 0.0);
        }
        let sigma_c = control_extinction(s, diagonal);
        tau_c.set(tau_c.get() + len as f64 * sigma_c as f64);
        ((s.max - sigma_c).max(sigma_c - s.min), sigma_c)
    };
    let control = |k: f32| (-(k as f64 * tau_c.get())).exp() as f32;
    walk(
        v,
        seg,
        rng,
        &mut lookups,
        Tracking {
            draws: 0,
            rate,
            collide: |_, sigma_t, sigma_r, sigma_c, rng: &mut Pcg32| {
                for (r, k) in ratio.iter_mut().zip(k) {
                    *r *= 1.0 - k * (sigma_t - sigma_c) / sigma_r;
                }
                threshold <= 0.0 || roulette(&mut ratio, k.map(control), threshold, rng)
            },
        },
    );
    let mut t = [0.0f32; N];
    for ((t, r), k) in t.iter_mut().zip(ratio).zip(k) {
        *t = control(k) * r;
    }
    (t, lookups)
}

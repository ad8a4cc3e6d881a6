//! The single place where estimators read the volume: counts the lookup and
//! draws the stochastic-filter jitter only when the filter uses it.

use fogbank_math::{pcg3d, rng::unit_f32, Pcg32, Vec3};
use fogbank_volume::VolumeAccess;

/// σ_t at index-space `p`, counting one full-resolution lookup. The jitter
/// for stochastic trilinear filtering is one PCG32 draw spread to three
/// dimensions by PCG3D (the GPU does the same).
#[inline(always)]
pub fn sigma_t_at<V: VolumeAccess>(v: &V, p: Vec3, rng: &mut Pcg32, lookups: &mut u32) -> f32 {
    *lookups += 1;
    let u = if v.needs_jitter() {
        let h = pcg3d([rng.next_u32(), *lookups, 0x9e37_79b9]);
        Vec3::new(unit_f32(h[0]), unit_f32(h[1]), unit_f32(h[2]))
    } else {
        Vec3::ZERO
    };
    v.sigma_t(p, u)
}

/// Exponential free-flight distance with rate `sigma_maj`: −ln(1 − u)/σ̄.
#[inline(always)]
pub fn sample_exponential(rng: &mut Pcg32, sigma_maj: f32) -> f32 {
    -(1.0 - rng.next_f32()).ln() / sigma_maj
}

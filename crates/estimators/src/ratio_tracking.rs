//! Ratio tracking (Novák et al. 2014; Peters 2025 §2.2): tentative collisions
//! from the super-voxel majorant, each weighting the estimate by the null
//! probability 1 − σ_t/σ̄ instead of terminating. Unbiased. With a
//! `roulette` threshold > 0 the walk plays Russian roulette once its weight
//! falls below it ([`crate::roulette`]), which bounds its cost in dense
//! media.

use crate::null_collisions::{walk, Tracking};
use crate::roulette::roulette;
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{SuperVoxel, VolumeAccess};

pub fn transmittance<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    rng: &mut Pcg32,
    threshold: f32,
) -> Estimate {
    Estimate::of_one_channel(transmittance_scaled(v, seg, rng, [1.0], threshold))
}

/// Ratio tracking of k_c σ_t for each channel c at once (k_c ≤ 1: the
/// majorant of σ_t bounds them all), weighting every channel at the same
/// tentative collisions. With k = [1] this is [`transmittance`] exactly.
pub fn transmittance_scaled<V: VolumeAccess, const N: usize>(
    v: &V,
    seg: &RaySegment,
    rng: &mut Pcg32,
    k: [f32; N],
    threshold: f32,
) -> ([f32; N], u32) {
    let mut lookups = 0;
    let mut tr = [1.0f32; N];
    walk(
        v,
        seg,
        rng,
        &mut lookups,
        Tracking {
            draws: 0,
            rate: |s: &SuperVoxel, _| (s.max, 0.0),
            collide: |_, sigma_t, sigma_maj, _, rng: &mut Pcg32| {
                for (t, k) in tr.iter_mut().zip(k) {
                    *t *= 1.0 - k * sigma_t / sigma_maj;
                }
                tr != [0.0; N] && roulette(&mut tr, [1.0; N], threshold, rng)
            },
        },
    );
    (tr, lookups)
}

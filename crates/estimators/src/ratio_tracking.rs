//! Ratio tracking (Novák et al. 2014; seed 000 §2.2): tentative collisions
//! from the super-voxel majorant, each weighting the estimate by the null
//! probability 1 − σ_t/σ̄ instead of terminating. Unbiased.

use crate::null_collisions::walk;
use crate::Estimate;
use fogbank_math::{Pcg32, Ray};
use fogbank_volume::VolumeAccess;

pub fn transmittance<V: VolumeAccess>(
    v: &V,
    ray: &Ray,
    t0: f32,
    t1: f32,
    rng: &mut Pcg32,
) -> Estimate {
    let mut lookups = 0;
    let mut tr = 1.0f32;
    walk(
        v,
        ray,
        t0,
        t1,
        rng,
        &mut lookups,
        |s, _| (s.max, 0.0),
        |_, sigma_t, sigma_maj, _, _| {
            tr *= 1.0 - sigma_t / sigma_maj;
            tr != 0.0
        },
    );
    Estimate {
        transmittance: tr,
        lookups,
    }
}

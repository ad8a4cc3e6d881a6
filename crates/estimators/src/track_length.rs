//! Track-length estimator (seed 000 §2.2): delta tracking over the
//! super-voxel majorant grid, returning 1 if no real collision happens before
//! the end of the segment and 0 otherwise. Unbiased, variance (1 − T)T.

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
    // A collision is real with probability σ_t/σ̄; the first one ends the walk.
    let escaped = walk(
        v,
        ray,
        t0,
        t1,
        rng,
        &mut lookups,
        |s, _| (s.max, 0.0),
        |_, sigma_t, sigma_maj, _, rng| rng.next_f32() * sigma_maj >= sigma_t,
    );
    Estimate {
        transmittance: if escaped { 1.0 } else { 0.0 },
        lookups,
    }
}

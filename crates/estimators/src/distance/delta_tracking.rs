//! Delta tracking (Woodcock; seed 000 §2.1) over the super-voxel majorant
//! grid: tentative collisions at rate σ̄, each real with probability σ_t/σ̄.

use super::FreeFlight;
use crate::null_collisions::walk;
use fogbank_math::{Pcg32, Ray};
use fogbank_volume::VolumeAccess;

pub fn sample<V: VolumeAccess>(v: &V, ray: &Ray, t0: f32, t1: f32, rng: &mut Pcg32) -> FreeFlight {
    let mut lookups = 0;
    let mut hit = None;
    walk(
        v,
        ray,
        t0,
        t1,
        rng,
        &mut lookups,
        |s, _| (s.max, 0.0),
        |t, sigma_t, sigma_maj, _, rng| {
            if rng.next_f32() * sigma_maj < sigma_t {
                hit = Some(t);
                false
            } else {
                true
            }
        },
    );
    FreeFlight { t: hit, lookups }
}

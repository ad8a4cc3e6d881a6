//! Track-length estimator (seed 000 §2.2): delta tracking over the
//! super-voxel majorant grid, returning 1 if no real collision happens before
//! the end of the segment and 0 otherwise. Unbiased, variance (1 − T)T.

use crate::lookup::{sample_exponential, sigma_t};
use crate::Estimate;
use fogbank_math::{Pcg32, Ray};
use fogbank_volume::{Dda, VolumeAccess};

pub fn transmittance<V: VolumeAccess>(
    v: &V,
    ray: &Ray,
    t0: f32,
    t1: f32,
    rng: &mut Pcg32,
) -> Estimate {
    let sv = v.supervoxels();
    let mut lookups = 0;
    for s in Dda::new(ray, sv.size as f32, sv.dims, t0, t1) {
        let sigma_maj = sv.get(s.cell).max;
        if sigma_maj <= 0.0 {
            continue;
        }
        // Memorylessness lets each super-voxel restart the exponential.
        let mut t = s.t0;
        loop {
            t += sample_exponential(rng, sigma_maj);
            if t >= s.t1 {
                break;
            }
            let mu = sigma_t(v, ray.at(t), rng, &mut lookups);
            if rng.next_f32() * sigma_maj < mu {
                return Estimate {
                    transmittance: 0.0,
                    lookups,
                };
            }
        }
    }
    Estimate {
        transmittance: 1.0,
        lookups,
    }
}

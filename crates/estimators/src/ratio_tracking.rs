//! Ratio tracking (Novák et al. 2014; seed 000 §2.2): tentative collisions
//! from the super-voxel majorant, each weighting the estimate by the null
//! probability 1 − σ_t/σ̄ instead of terminating. Unbiased.

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
    let mut tr = 1.0f32;
    for s in Dda::new(ray, sv.size as f32, sv.dims, t0, t1) {
        let sigma_maj = sv.get(s.cell).max;
        if sigma_maj <= 0.0 {
            continue;
        }
        let mut t = s.t0;
        loop {
            t += sample_exponential(rng, sigma_maj);
            if t >= s.t1 {
                break;
            }
            let mu = sigma_t(v, ray.at(t), rng, &mut lookups);
            tr *= 1.0 - mu / sigma_maj;
        }
        if tr == 0.0 {
            break;
        }
    }
    Estimate {
        transmittance: tr,
        lookups,
    }
}

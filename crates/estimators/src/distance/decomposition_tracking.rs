//! Decomposition tracking (Kutz et al. 2017) with the super-voxel minimum as
//! control: σ_t = σ_min + (σ_t − σ_min). The control part is homogeneous per
//! super-voxel, so its collision is sampled analytically (no lookup); the
//! residual is delta-tracked with majorant σ_max − σ_min. The earlier of the
//! two is the real collision. In a homogeneous super-voxel this never reads
//! the volume.

use super::FreeFlight;
use crate::lookup::{sample_exponential, sigma_t_at};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{Dda, VolumeAccess};

pub fn sample<V: VolumeAccess>(v: &V, seg: &RaySegment, rng: &mut Pcg32) -> FreeFlight {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let sv = v.supervoxels();
    let mut lookups = 0;
    for s in Dda::new(ray, sv.size as f32, sv.dims, t0, t1) {
        let cell = sv.get(s.cell);
        if cell.max <= 0.0 {
            continue;
        }
        // Control collision inside this super-voxel (memoryless: restart).
        let t_control = if cell.min > 0.0 {
            s.t0 + sample_exponential(rng, cell.min)
        } else {
            f32::INFINITY
        };
        let limit = t_control.min(s.t1);
        let sigma_r = cell.max - cell.min;
        if sigma_r > 0.0 {
            let mut t = s.t0;
            loop {
                t += sample_exponential(rng, sigma_r);
                if t >= limit {
                    break;
                }
                let sigma_t = sigma_t_at(v, ray.at(t), rng, &mut lookups);
                if rng.next_f32() * sigma_r < sigma_t - cell.min {
                    return FreeFlight {
                        t: Some(t),
                        lookups,
                    };
                }
            }
        }
        if t_control < s.t1 {
            return FreeFlight {
                t: Some(t_control),
                lookups,
            };
        }
    }
    FreeFlight { t: None, lookups }
}

//! The tentative (null-collision) process shared by the tracking
//! estimators: a Poisson process along the ray whose rate is constant within
//! each super-voxel (its majorant), restarted per super-voxel since the
//! exponential is memoryless. Each collision reads σ_t once.

use crate::lookup::{sample_exponential, sigma_t_at};
use fogbank_math::{Pcg32, Ray};
use fogbank_volume::{Dda, SuperVoxel, VolumeAccess};

/// Walks `[t0, t1]`. `rate(cell, length)` gives a super-voxel's rate and a
/// value handed to its collisions (e.g. a control extinction); `collide(t, μ,
/// rate, value, rng)` handles one tentative collision at `t` and returns
/// `false` to stop the walk. Returns whether the walk reached `t1`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn walk<V: VolumeAccess>(
    v: &V,
    ray: &Ray,
    t0: f32,
    t1: f32,
    rng: &mut Pcg32,
    lookups: &mut u32,
    mut rate: impl FnMut(&SuperVoxel, f32) -> (f32, f32),
    mut collide: impl FnMut(f32, f32, f32, f32, &mut Pcg32) -> bool,
) -> bool {
    let sv = v.supervoxels();
    for s in Dda::new(ray, sv.size as f32, sv.dims, t0, t1) {
        let (sigma_maj, value) = rate(sv.get(s.cell), s.t1 - s.t0);
        if sigma_maj <= 0.0 {
            continue;
        }
        let mut t = s.t0;
        loop {
            t += sample_exponential(rng, sigma_maj);
            if t >= s.t1 {
                break;
            }
            let sigma_t = sigma_t_at(v, ray.at(t), rng, lookups);
            if !collide(t, sigma_t, sigma_maj, value, rng) {
                return false;
            }
        }
    }
    true
}

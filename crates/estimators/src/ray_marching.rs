//! Naive ray marching: N equidistant samples sharing one jitter over the
//! segment, T = exp(−X). Biased (Jensen: it overestimates T). With `clip`,
//! the segment is first shrunk to the non-empty super-voxels.

use crate::lookup::LookupBatch;
use crate::optical_depth::{prepare, Importance};
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::VolumeAccess;

pub fn transmittance<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    samples: u32,
    clip: bool,
    rng: &mut Pcg32,
) -> Estimate {
    let (x, lookups) = optical_depth(v, seg, samples, clip, rng);
    Estimate {
        transmittance: (-x).exp() as f32,
        lookups,
    }
}

/// The marched optical depth X and the lookups taken (X = 0 without a
/// lookup when `clip` finds the segment empty).
pub fn optical_depth<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    samples: u32,
    clip: bool,
    rng: &mut Pcg32,
) -> (f64, u32) {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let (a, b) = if clip {
        let p = prepare(v, seg, Importance::Mean);
        if p.total <= 0.0 {
            return (0.0, 0);
        }
        (p.t_min, p.t_max)
    } else {
        (t0, t1)
    };
    let n = samples.max(1);
    let dt = (b - a) as f64 / n as f64;
    let u = rng.next_f32() as f64;
    let mut lookups = 0;
    let mut sum = 0.0f64;
    // Read in batches (SIMD lanes), summed in order: the sequential sum.
    let mut batch = LookupBatch::<()>::default();
    for i in 0..n {
        let t = a as f64 + (i as f64 + u) * dt;
        if batch.push(v, ray.at(t as f32), (), rng, &mut lookups) {
            batch.drain(v, |sigma_t, ()| sum += sigma_t as f64);
        }
    }
    batch.drain(v, |sigma_t, ()| sum += sigma_t as f64);
    (sum * dt, lookups)
}

//! Deterministic ray marching of the trilinear field (Lin et al. 2021 §4.3, §5.1):
//! the T̃ inside the reuse target p̂, which must return the same value every
//! time a path is evaluated (p̂_new/p̂_old ratios, Talbot sums), so it draws
//! no random numbers and never filters stochastically. Midpoints of steps
//! of a fixed length on a grid anchored at the segment's start (the
//! authors' code anchors at the ray's entry into the volume); the last step
//! is cut at the segment's end. On mip 1 with a step of one mip-1 voxel
//! diagonal this is the paper's reuse T̃.

use fogbank_math::{RaySegment, Vec3};
use fogbank_volume::{Filter, GridView, Occupied, Voxel, ZERO_TRILINEAR};

/// (τ̃, lookups) over `[t0, t1]` of the index-space `ray`, with steps of
/// `step` index-space units (voxels) along the ray; the field is read
/// trilinearly whatever the view's own filter.
pub fn optical_depth<T: Voxel>(v: &GridView<'_, T>, seg: &RaySegment, step: f32) -> (f64, u32) {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let speed = ray.d.length() as f64;
    // Also refuses NaN bounds or steps: every comparison with NaN is false.
    let valid = t1 > t0 && step > 0.0 && speed > 0.0;
    if !valid {
        return (0.0, 0);
    }
    let dt = step as f64 / speed;
    let (a, b) = (t0 as f64, t1 as f64);
    let n = ((b - a) / dt).ceil().max(1.0) as u64;
    let mut tau = 0.0f64;
    let mut lookups = 0u64;
    // Only the steps that reach a super-voxel where the field may be
    // non-zero: the others would add exact zeros, so τ̃ is the same sum, bit
    // for bit, in the same order (`next` keeps a step shared by two spans
    // from counting twice).
    let mut next = 0u64;
    // The midpoints are known before any value is read: read them eight at
    // a time in SIMD lanes (bit for bit `filtered`) and add them in order.
    let (mut p, mut w, mut k) = ([Vec3::ZERO; LANES], [0.0f64; LANES], 0);
    let add = |p: &[Vec3], w: &[f64], tau: &mut f64| {
        let mut s = [0.0f32; LANES];
        v.grid.filtered_lanes(Filter::Trilinear, p, &[], &mut s);
        for (s, w) in s.iter().zip(w) {
            *tau += v.classify(*s) as f64 * w;
        }
    };
    for (ta, tb) in Occupied::new(v.supervoxels, ZERO_TRILINEAR, ray, t0, t1) {
        let first = (((ta as f64 - a) / dt).floor().max(0.0) as u64).max(next);
        let end = (((tb as f64 - a) / dt).floor() as u64 + 1).min(n);
        for i in first..end {
            let lo = a + i as f64 * dt;
            let hi = (lo + dt).min(b);
            let mid = 0.5 * (lo + hi);
            (p[k], w[k]) = (ray.at(mid as f32), hi - lo);
            k += 1;
            if k == LANES {
                add(&p, &w, &mut tau);
                k = 0;
            }
            lookups += 1;
        }
        next = next.max(end);
    }
    add(&p[..k], &w[..k], &mut tau);
    (tau * v.scale as f64, lookups.min(u32::MAX as u64) as u32)
}

/// Midpoints read per lanes call.
const LANES: usize = 8;

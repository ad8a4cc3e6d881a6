//! BC4-style block compression of a grid (Lin et al. 2021 §5.1: the paper stores
//! mip 1 as BC4, 4 bits a voxel): each 4×4 block of voxels in an x–y slice
//! keeps two 8-bit endpoints (its maximum and minimum, as fractions of the
//! grid's maximum) and a 3-bit index per voxel into the eight values
//! between them (the endpoints and six interpolants, BC4's 8-value mode).
//! fogbank decodes the blocks once into an f32 grid, so the lookups stay
//! those of any grid; what the option changes is the values, exactly as a
//! GPU's BC4 texture would, and [`BC4_BITS_PER_VOXEL`] is the storage the
//! compressed form would take.

use crate::error::Result;
use crate::grid::BrickGrid;

/// Storage of the compressed form: 64 bits per 16 voxels.
pub const BC4_BITS_PER_VOXEL: f64 = 4.0;

/// The grid after a BC4 encode–decode round trip (`fetch` reads voxels
/// inside `dims`).
pub fn bc4_roundtrip(
    dims: [u32; 3],
    fetch: impl Fn(i32, i32, i32) -> f32 + Sync,
) -> Result<BrickGrid<f32>> {
    let mut peak = 0.0f32;
    for k in 0..dims[2] as i32 {
        for j in 0..dims[1] as i32 {
            for i in 0..dims[0] as i32 {
                peak = peak.max(fetch(i, j, k));
            }
        }
    }
    let quantise = |v: f32| -> u8 {
        if peak > 0.0 {
            (v.max(0.0) / peak * 255.0).round().clamp(0.0, 255.0) as u8
        } else {
            0
        }
    };
    BrickGrid::from_fn(dims, |i, j, k| {
        let (bi, bj) = ((i / 4 * 4) as i32, (j / 4 * 4) as i32);
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for y in bj..(bj + 4).min(dims[1] as i32) {
            for x in bi..(bi + 4).min(dims[0] as i32) {
                let v = fetch(x, y, k as i32);
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        let (c0, c1) = (quantise(hi) as f32, quantise(lo) as f32);
        let v = fetch(i as i32, j as i32, k as i32).max(0.0) / peak.max(f32::MIN_POSITIVE) * 255.0;
        // The eight palette values: c0, c1 and (7−n)·c0 + n·c1 over 7.
        let mut best = c0;
        for n in 0..8 {
            let p = match n {
                0 => c0,
                1 => c1,
                n => ((8 - n) as f32 * c0 + (n - 1) as f32 * c1) / 7.0,
            };
            if (p - v).abs() < (best - v).abs() {
                best = p;
            }
        }
        best / 255.0 * peak
    })
}

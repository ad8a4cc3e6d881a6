//! Conservative piecewise-constant mips of a density grid (Lin et al. 2021 §4.1),
//! for regular tracking through a coarse volume: σ_t* of level `l` is
//! constant per mip voxel of 2^l fine voxels a side.
//!
//! A mip voxel holds the mean of the fine voxels it covers. Where that mean
//! is 0 although the trilinear field of the fine grid is positive somewhere
//! in its footprint (a fine voxel within one voxel of the block is
//! positive), it takes the mean of its 26 neighbours at that level, so
//! σ_t* > 0 wherever the trilinear σ_t > 0 ("conservative"; the authors'
//! code does the same fix-up). Distance sampling through σ_t* then reaches
//! every point the full-resolution integrand can be non-zero at.
//!
//! Mip voxel `j` covers fine voxels `[j·2^l, (j+1)·2^l)`; a partial block at
//! the far border averages the fine voxels it has, and the mip's index box
//! may reach up to 2^l − 1 fine voxels past the fine one.

use crate::access::Filter;
use crate::error::{Result, VolumeError};
use crate::grid::{BrickGrid, Precision};
use crate::medium::{DensityData, Medium};
use fogbank_math::{DAffine3, DVec3};

/// Highest mip level fogbank builds (2⁸ = 256 fine voxels per mip voxel).
pub const MAX_LEVEL: u32 = 8;

/// Mip `level` (1 ..= [`MAX_LEVEL`]) of the non-negative grid of `dims`
/// read through `fetch` (indices inside the grid).
pub fn mip_grid(
    dims: [u32; 3],
    fetch: impl Fn(i32, i32, i32) -> f32 + Sync,
    level: u32,
) -> Result<BrickGrid<f32>> {
    if level == 0 || level > MAX_LEVEL {
        return Err(VolumeError::Invalid(format!(
            "mip level {level} is outside 1..={MAX_LEVEL}"
        )));
    }
    let s = 1i32 << level;
    let coarse = dims.map(|d| d.div_ceil(s as u32).max(1));
    let d = dims.map(|x| x as i32);
    let in_grid = |i: i32, j: i32, k: i32| i < d[0] && j < d[1] && k < d[2];
    // The block means.
    let means = BrickGrid::<f32>::from_fn(coarse, |ci, cj, ck| {
        let (mut sum, mut n) = (0.0f64, 0u32);
        let o = [ci as i32 * s, cj as i32 * s, ck as i32 * s];
        for k in o[2]..o[2] + s {
            for j in o[1]..o[1] + s {
                for i in o[0]..o[0] + s {
                    if in_grid(i, j, k) {
                        sum += fetch(i, j, k).max(0.0) as f64;
                        n += 1;
                    }
                }
            }
        }
        if n == 0 {
            0.0
        } else {
            (sum / n as f64) as f32
        }
    })?;
    let c = coarse.map(|x| x as i32);
    BrickGrid::<f32>::from_fn(coarse, |ci, cj, ck| {
        let (ci, cj, ck) = (ci as i32, cj as i32, ck as i32);
        let m = means.fetch(ci, cj, ck);
        if m > 0.0 {
            return m;
        }
        // A zero block has only zero voxels (densities are ≥ 0), so its
        // apron can be positive only where a neighbouring block is.
        let (mut sum, mut n, mut positive) = (0.0f64, 0u32, false);
        for dk in -1..=1 {
            for dj in -1..=1 {
                for di in -1..=1 {
                    let (i, j, k) = (ci + di, cj + dj, ck + dk);
                    if (di, dj, dk) == (0, 0, 0)
                        || i < 0
                        || j < 0
                        || k < 0
                        || i >= c[0]
                        || j >= c[1]
                        || k >= c[2]
                    {
                        continue;
                    }
                    let v = means.fetch(i, j, k);
                    positive |= v > 0.0;
                    sum += v as f64;
                    n += 1;
                }
            }
        }
        if !positive || !apron_positive(&fetch, d, [ci * s, cj * s, ck * s], s) {
            return 0.0;
        }
        (sum / n as f64) as f32
    })
}

/// Whether a fine voxel within one voxel of the block at `o` (edge `s`) is
/// positive: the trilinear field (clamped at the grid's edge, as lookups
/// are) is then positive somewhere in the block.
fn apron_positive(fetch: &impl Fn(i32, i32, i32) -> f32, d: [i32; 3], o: [i32; 3], s: i32) -> bool {
    let clamp = |x: i32, a: usize| x.clamp(0, d[a] - 1);
    for k in o[2] - 1..=o[2] + s {
        for j in o[1] - 1..=o[1] + s {
            for i in o[0] - 1..=o[0] + s {
                if fetch(clamp(i, 0), clamp(j, 1), clamp(k, 2)) > 0.0 {
                    return true;
                }
            }
        }
    }
    false
}

impl Medium {
    /// This medium's mip `level` as a medium of its own: nearest filter,
    /// the same σ_t scale and placement (a mip voxel covers 2^level fine
    /// voxels a side), super-voxels of `supervoxel` mip voxels, stored in
    /// f32 (f16 could round a small positive mean to 0). Analytic media have
    /// no mips.
    pub fn mip(&self, level: u32, supervoxel: u32) -> Result<Medium> {
        let grid = match &self.data {
            DensityData::F16(g) => mip_grid(g.dims(), |i, j, k| g.fetch(i, j, k), level)?,
            DensityData::F32(g) => mip_grid(g.dims(), |i, j, k| g.fetch(i, j, k), level)?,
            DensityData::Analytic(_) => {
                return Err(VolumeError::Invalid(
                    "analytic media have no mips; use a voxel grid".into(),
                ))
            }
        };
        let s = (1u32 << level) as f64;
        let to_world = self.index_to_world * DAffine3::from_scale(DVec3::splat(s));
        Ok(Medium::new(
            DensityData::from_f32(grid, Precision::F32),
            self.sigma_t_scale,
            Filter::Nearest,
            to_world,
            supervoxel,
        ))
    }
}

impl Medium {
    /// This grid medium with its values through a BC4 encode–decode round
    /// trip ([`crate::bc4`]), same placement, filter and super-voxel size.
    pub fn bc4(&self, supervoxel: u32) -> Result<Medium> {
        let grid = match &self.data {
            DensityData::F16(g) => crate::bc4::bc4_roundtrip(g.dims(), |i, j, k| g.fetch(i, j, k))?,
            DensityData::F32(g) => crate::bc4::bc4_roundtrip(g.dims(), |i, j, k| g.fetch(i, j, k))?,
            DensityData::Analytic(_) => {
                return Err(VolumeError::Invalid(
                    "analytic media have no voxels to compress".into(),
                ))
            }
        };
        Ok(Medium::new(
            DensityData::from_f32(grid, Precision::F32),
            self.sigma_t_scale,
            self.filter,
            self.index_to_world,
            supervoxel,
        ))
    }
}

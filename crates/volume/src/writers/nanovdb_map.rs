//! The index→world map as NanoVDB stores it (`Map` in `NanoVDB.h`): the
//! matrix, its inverse and the translation in `f64` and rounded to `f32`,
//! and what the grid derives from it: the world box of the active voxels
//! and the voxel size.

use super::nanovdb_stats::Stats;
use crate::loaders::vdb::VdbGrid;
use crate::{Result, VolumeError};

/// The index→world map in NanoVDB's form: matrix, inverse and translation
/// in `f64`, and rounded to `f32`.
pub(crate) struct Map {
    pub(crate) mat: [[f64; 3]; 3],
    pub(crate) inv: [[f64; 3]; 3],
    pub(crate) vec: [f64; 3],
}

impl Map {
    pub(crate) fn new(g: &VdbGrid) -> Result<Map> {
        let m = &g.index_to_world;
        let l = glam::DMat3::from_cols_array_2d(&std::array::from_fn(|c| {
            std::array::from_fn(|r| m[r][c])
        }));
        let det = l.determinant();
        if !(det.is_finite() && det != 0.0) || m.iter().flatten().any(|v| !v.is_finite()) {
            return Err(VolumeError::Invalid(format!(
                "grid `{}`: index-to-world map is not an invertible affine map",
                g.name
            )));
        }
        let i = l.inverse();
        Ok(Map {
            mat: std::array::from_fn(|r| std::array::from_fn(|c| m[r][c])),
            inv: std::array::from_fn(|r| std::array::from_fn(|c| i.col(c)[r])),
            vec: [m[0][3], m[1][3], m[2][3]],
        })
    }

    /// `mat · p + vec` with fused multiply-adds, as NanoVDB's `applyMap`.
    fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|r| {
            let m = self.mat[r];
            p[0].mul_add(m[0], p[1].mul_add(m[1], p[2].mul_add(m[2], self.vec[r])))
        })
    }

    /// The box of the world images of the index box `[lo, hi + 1]`.
    pub(crate) fn world_bbox(&self, s: &Stats) -> [f64; 6] {
        if s.is_empty() {
            return [0.0; 6];
        }
        let mut b = [f64::MAX, f64::MAX, f64::MAX, f64::MIN, f64::MIN, f64::MIN];
        for corner in 0..8 {
            let p = std::array::from_fn(|k| match corner >> k & 1 {
                0 => s.lo[k] as f64,
                _ => s.hi[k] as f64 + 1.0,
            });
            for (k, w) in self.apply(p).into_iter().enumerate() {
                b[k] = b[k].min(w);
                b[k + 3] = b[k + 3].max(w);
            }
        }
        b
    }

    /// The voxel size as OpenVDB reports it (and its converter stores
    /// it): the scale of a uniform scale map, else the lengths of the
    /// images of the index axes, `(M·e + t) − t`.
    pub(crate) fn voxel_size(&self) -> [f64; 3] {
        let m = &self.mat;
        let s = m[0][0];
        if (0..3).all(|r| (0..3).all(|c| m[r][c] == if r == c { s } else { 0.0 })) {
            return [s; 3];
        }
        std::array::from_fn(|c| {
            let d: [f64; 3] = std::array::from_fn(|r| (m[r][c] + self.vec[r]) - self.vec[r]);
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
    }
}

//! The narrow volume-access interface every estimator is written against.
//!
//! Estimators are generic over [`VolumeAccess`], so the hot loop is
//! monomorphised per storage type with no dynamic dispatch, and the WGSL port
//! implements the same three operations: a filtered extinction lookup, the
//! super-voxel statistics, and the index-space box.

use crate::grid::{BrickGrid, Voxel};
use crate::supervoxel::SuperVoxelGrid;
use fogbank_math::Vec3;

/// Reconstruction filter of a voxel grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    /// Value of the voxel containing the point (piecewise constant).
    Nearest,
    /// Trilinear interpolation between voxel centres.
    Trilinear,
    /// Nearest lookup after a uniform jitter in [−½, ½)³ of the continuous
    /// position; its expectation is the trilinear interpolant (seed 000 §6).
    #[default]
    StochasticTrilinear,
}

impl Filter {
    pub fn name(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Trilinear => "trilinear",
            Filter::StochasticTrilinear => "stochastic_trilinear",
        }
    }

    pub fn parse(s: &str) -> Option<Filter> {
        match s {
            "nearest" => Some(Filter::Nearest),
            "trilinear" => Some(Filter::Trilinear),
            "stochastic_trilinear" => Some(Filter::StochasticTrilinear),
            _ => None,
        }
    }

    /// Voxels a filtered lookup inside a cell may read beyond the cell.
    pub fn apron(self) -> u32 {
        match self {
            Filter::Nearest => 0,
            _ => 1,
        }
    }
}

pub trait VolumeAccess: Sync {
    /// Extinction σ_t at index-space point `p` (inside `[0, dims]`). `u` is a
    /// uniform point in [0, 1)³, used only by stochastic filtering.
    fn sigma_t(&self, p: Vec3, u: Vec3) -> f32;
    /// Whether `sigma_t` reads `u` (callers skip drawing it otherwise).
    fn needs_jitter(&self) -> bool;
    /// Super-voxel statistics in extinction units.
    fn supervoxels(&self) -> &SuperVoxelGrid;
    /// Index-space extent: the medium occupies `[0, dims]`.
    fn dims(&self) -> [u32; 3];
}

/// A voxel grid seen through a filter and an extinction scale.
pub struct GridView<'a, T> {
    pub grid: &'a BrickGrid<T>,
    pub filter: Filter,
    pub scale: f32,
    pub supervoxels: &'a SuperVoxelGrid,
}

impl<T: Voxel> BrickGrid<T> {
    #[inline(always)]
    pub fn nearest(&self, p: Vec3) -> f32 {
        self.fetch(p.x.floor() as i32, p.y.floor() as i32, p.z.floor() as i32)
    }

    /// Trilinear interpolation between voxel centres, clamped at the border.
    #[inline(always)]
    pub fn trilinear(&self, p: Vec3) -> f32 {
        let q = p - Vec3::splat(0.5);
        let f = q.floor();
        let w = q - f;
        let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
        let c000 = self.fetch(i, j, k);
        let c100 = self.fetch(i + 1, j, k);
        let c010 = self.fetch(i, j + 1, k);
        let c110 = self.fetch(i + 1, j + 1, k);
        let c001 = self.fetch(i, j, k + 1);
        let c101 = self.fetch(i + 1, j, k + 1);
        let c011 = self.fetch(i, j + 1, k + 1);
        let c111 = self.fetch(i + 1, j + 1, k + 1);
        let c00 = c000 + w.x * (c100 - c000);
        let c10 = c010 + w.x * (c110 - c010);
        let c01 = c001 + w.x * (c101 - c001);
        let c11 = c011 + w.x * (c111 - c011);
        let c0 = c00 + w.y * (c10 - c00);
        let c1 = c01 + w.y * (c11 - c01);
        c0 + w.z * (c1 - c0)
    }

    #[inline(always)]
    pub fn filtered(&self, filter: Filter, p: Vec3, u: Vec3) -> f32 {
        match filter {
            Filter::Nearest => self.nearest(p),
            Filter::Trilinear => self.trilinear(p),
            Filter::StochasticTrilinear => self.nearest(p + u - Vec3::splat(0.5)),
        }
    }
}

impl<T: Voxel> VolumeAccess for GridView<'_, T> {
    #[inline(always)]
    fn sigma_t(&self, p: Vec3, u: Vec3) -> f32 {
        self.scale * self.grid.filtered(self.filter, p, u)
    }
    #[inline(always)]
    fn needs_jitter(&self) -> bool {
        self.filter == Filter::StochasticTrilinear
    }
    #[inline(always)]
    fn supervoxels(&self) -> &SuperVoxelGrid {
        self.supervoxels
    }
    #[inline(always)]
    fn dims(&self) -> [u32; 3] {
        self.grid.dims()
    }
}

#[cfg(test)]
mod access_test {
    use super::*;
    use fogbank_math::Pcg32;

    #[test]
    fn stochastic_trilinear_expectation_is_trilinear() {
        let g =
            BrickGrid::<f32>::from_fn([6, 5, 4], |i, j, k| ((i * 7 + j * 3 + k * 5) % 11) as f32)
                .unwrap();
        let mut rng = Pcg32::new(3, 9);
        for p in [
            Vec3::new(2.3, 1.7, 2.9),
            Vec3::new(0.2, 4.9, 0.6),
            Vec3::new(5.5, 2.5, 1.5),
        ] {
            let n = 200_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                let v = g.filtered(Filter::StochasticTrilinear, p, u) as f64;
                s += v;
                s2 += v * v;
            }
            let mean = s / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            let exact = g.trilinear(p) as f64;
            assert!(
                (mean - exact).abs() < 4.0 * se + 1e-9,
                "{p}: {mean} vs {exact} (se {se})"
            );
        }
    }

    #[test]
    fn trilinear_hits_voxel_centres() {
        let g =
            BrickGrid::<f32>::from_fn([4, 4, 4], |i, j, k| (i + 4 * j + 16 * k) as f32).unwrap();
        assert_eq!(g.trilinear(Vec3::new(1.5, 2.5, 3.5)), (1 + 8 + 48) as f32);
        assert_eq!(g.nearest(Vec3::new(1.99, 2.0, 3.5)), (1 + 8 + 48) as f32);
        // Clamped at the border: constant within half a voxel of the edge.
        assert_eq!(g.trilinear(Vec3::new(0.1, 0.5, 0.5)), 0.0);
    }
}

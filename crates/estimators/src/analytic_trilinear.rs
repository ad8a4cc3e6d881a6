//! Exact optical depth of the trilinear interpolant (Lin et al. 2021 §5 "analytic
//! trilinear"; the ground truth for trilinear and stochastic-trilinear media).
//!
//! Between voxel centres the field is trilinear, so along a ray segment inside
//! one dual cell it is a cubic polynomial in t. Two-point Gauss–Legendre
//! quadrature integrates cubics exactly, which gives the closed-form integral
//! with two evaluations per cell. Computed in f64.

use fogbank_math::{Ray, RaySegment, Vec3};
use fogbank_volume::{BrickGrid, Dda, GridView, Occupied, Voxel, ZERO_TRILINEAR};
use glam::DVec3;

const GL_NODE: f64 = 0.577_350_269_189_625_8; // 1/√3

/// The trilinear field inside one dual cell (the eight voxel centres around
/// it), evaluated along a ray: a cubic in the ray parameter.
#[derive(Clone, Copy, Debug)]
pub struct DualCell {
    corners: [f64; 8],
    base: DVec3,
}

impl DualCell {
    /// Dual cell `cell` of `g` (cell c spans voxel centres c − 1 … c).
    #[inline]
    pub fn new<T: Voxel>(g: &BrickGrid<T>, cell: [i32; 3]) -> DualCell {
        let [ci, cj, ck] = cell;
        let c = |di: i32, dj: i32, dk: i32| g.fetch(ci - 1 + di, cj - 1 + dj, ck - 1 + dk) as f64;
        DualCell {
            corners: [
                c(0, 0, 0),
                c(1, 0, 0),
                c(0, 1, 0),
                c(1, 1, 0),
                c(0, 0, 1),
                c(1, 0, 1),
                c(0, 1, 1),
                c(1, 1, 1),
            ],
            base: DVec3::new(ci as f64, cj as f64, ck as f64),
        }
    }

    /// The field at parameter `t` of the (shifted) ray `o + t d`.
    #[inline]
    pub fn value(&self, o: DVec3, d: DVec3, t: f64) -> f64 {
        let c = &self.corners;
        let w = (o + t * d - self.base).clamp(DVec3::ZERO, DVec3::ONE);
        let x0 = c[0] + w.x * (c[1] - c[0]);
        let x1 = c[2] + w.x * (c[3] - c[2]);
        let x2 = c[4] + w.x * (c[5] - c[4]);
        let x3 = c[6] + w.x * (c[7] - c[6]);
        let y0 = x0 + w.y * (x1 - x0);
        let y1 = x2 + w.y * (x3 - x2);
        y0 + w.z * (y1 - y0)
    }

    /// ∫_a^b of the field: two-point Gauss–Legendre, exact for the cubic.
    #[inline]
    pub fn integral(&self, o: DVec3, d: DVec3, a: f64, b: f64) -> f64 {
        let mid = 0.5 * (a + b);
        let half = 0.5 * (b - a);
        let mut sum = 0.0;
        for t in [mid - half * GL_NODE, mid + half * GL_NODE] {
            sum += self.value(o, d, t);
        }
        sum * half
    }
}

/// The ray shifted by +½ so that dual cell c spans voxel centres c−1 … c
/// and the grid box [0, dims] lies inside the cells [0, dims + 1).
pub fn shifted(ray: &Ray, dims: [u32; 3]) -> (Ray, [u32; 3]) {
    (
        Ray::new(ray.o + Vec3::splat(0.5), ray.d),
        dims.map(|d| d + 1),
    )
}

/// τ over `[t0, t1]` (clipped to the grid box `[0, dims]`). Returns
/// (τ, lookups = dual cells visited; each reads eight voxels). Skips the
/// super-voxels where the field is zero ([`Occupied`]); a dual cell cut by
/// a span's end is integrated in pieces, which sum to the same cubic's
/// integral.
/// The dual-grid frame of `ray` for the exact integrals: the ray [`shifted`]
/// half a voxel, the dual grid's size, and the shifted origin and direction
/// in f64. Exact only for the trilinear field itself: scenes refuse this
/// estimator for media classified by a transfer function.
pub fn dual_frame<T: Voxel>(v: &GridView<'_, T>, ray: &Ray) -> (Ray, [u32; 3], DVec3, DVec3) {
    debug_assert!(
        v.opacity.is_none(),
        "analytic_trilinear on a classified medium"
    );
    let (shifted, n) = shifted(ray, v.grid.dims());
    (shifted, n, shifted.o.as_dvec3(), shifted.d.as_dvec3())
}

pub fn optical_depth<T: Voxel>(v: &GridView<'_, T>, seg: &RaySegment) -> (f64, u32) {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let (shifted, n, o, d) = dual_frame(v, ray);
    let mut tau = 0.0f64;
    let mut lookups = 0;
    for (ta, tb) in Occupied::new(v.supervoxels, ZERO_TRILINEAR, ray, t0, t1) {
        for s in Dda::new(&shifted, 1.0, n, ta, tb) {
            let len = (s.t1 - s.t0) as f64;
            if len <= 0.0 {
                continue;
            }
            lookups += 1;
            tau += DualCell::new(v.grid, s.cell).integral(o, d, s.t0 as f64, s.t1 as f64);
        }
    }
    (tau * v.scale as f64, lookups)
}

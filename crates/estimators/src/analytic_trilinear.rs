//! Exact optical depth of the trilinear interpolant (seed 002 §5 "analytic
//! trilinear"; the ground truth for trilinear and stochastic-trilinear media).
//!
//! Between voxel centres the field is trilinear, so along a ray segment inside
//! one dual cell it is a cubic polynomial in t. Two-point Gauss–Legendre
//! quadrature integrates cubics exactly, which gives the closed-form integral
//! with two evaluations per cell. Computed in f64.

use fogbank_math::{Ray, Vec3};
use fogbank_volume::{Dda, GridView, Voxel};

const GL_NODE: f64 = 0.577_350_269_189_625_8; // 1/√3

/// τ over `[t0, t1]` (clipped to the grid box `[0, dims]`). Returns
/// (τ, lookups = dual cells visited; each reads eight voxels).
pub fn optical_depth<T: Voxel>(v: &GridView<'_, T>, ray: &Ray, t0: f32, t1: f32) -> (f64, u32) {
    let g = v.grid;
    let dims = g.dims();
    // Shift by +½ so dual cell c spans voxel centres c−1 … c and the grid
    // box [0, dims] lies inside the cells [0, dims + 1).
    let shifted = Ray::new(ray.o + Vec3::splat(0.5), ray.d);
    let n = dims.map(|d| d + 1);
    let (o, d) = (shifted.o.as_dvec3(), shifted.d.as_dvec3());
    let mut tau = 0.0f64;
    let mut lookups = 0;
    for s in Dda::new(&shifted, 1.0, n, t0, t1) {
        let len = (s.t1 - s.t0) as f64;
        if len <= 0.0 {
            continue;
        }
        lookups += 1;
        let [ci, cj, ck] = s.cell;
        let c = |di: i32, dj: i32, dk: i32| g.fetch(ci - 1 + di, cj - 1 + dj, ck - 1 + dk) as f64;
        let corners = [
            c(0, 0, 0),
            c(1, 0, 0),
            c(0, 1, 0),
            c(1, 1, 0),
            c(0, 0, 1),
            c(1, 0, 1),
            c(0, 1, 1),
            c(1, 1, 1),
        ];
        let base = glam::DVec3::new(ci as f64, cj as f64, ck as f64);
        let mid = 0.5 * (s.t0 as f64 + s.t1 as f64);
        let half = 0.5 * len;
        let mut sum = 0.0;
        for t in [mid - half * GL_NODE, mid + half * GL_NODE] {
            let w = (o + t * d - base).clamp(glam::DVec3::ZERO, glam::DVec3::ONE);
            let x0 = corners[0] + w.x * (corners[1] - corners[0]);
            let x1 = corners[2] + w.x * (corners[3] - corners[2]);
            let x2 = corners[4] + w.x * (corners[5] - corners[4]);
            let x3 = corners[6] + w.x * (corners[7] - corners[6]);
            let y0 = x0 + w.y * (x1 - x0);
            let y1 = x2 + w.y * (x3 - x2);
            sum += y0 + w.z * (y1 - y0);
        }
        tau += sum * half;
    }
    (tau * v.scale as f64, lookups)
}

//! Regular tracking (Szirmay-Kalos et al. 2010; Peters 2025 §2.1): the exact
//! optical depth of the piecewise-constant (nearest-filtered) grid, summed
//! voxel by voxel along a DDA. Deterministic; its cost is the worst case.

use fogbank_math::RaySegment;
use fogbank_volume::{Dda, GridView, Voxel};

/// τ = Σ_voxels σ_t(voxel) · Δt over `[t0, t1]` (already clipped to the
/// grid). Returns (τ, lookups = voxels visited).
pub fn optical_depth<T: Voxel>(v: &GridView<'_, T>, seg: &RaySegment) -> (f64, u32) {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let mut tau = 0.0f64;
    let mut lookups = 0;
    for s in Dda::new(ray, 1.0, v.grid.dims(), t0, t1) {
        lookups += 1;
        let sigma_t = v.classify(v.grid.fetch(s.cell[0], s.cell[1], s.cell[2]));
        tau += sigma_t as f64 * (s.t1 - s.t0) as f64;
    }
    (tau * v.scale as f64, lookups)
}

// fogbank_estimators::regular_tracking: the optical depth of the
// nearest-filtered grid, voxel by voxel; exact, so T = exp(−τ).

fn regular_tracking(m: MediumGpu, r: Ray, t0: f32, t1: f32, lookups: ptr<function, u32>) -> f32 {
    return exp(-regular_tracking_tau(m, r, t0, t1, lookups));
}

// regular_tracking::optical_depth: τ itself (scaled.rs shares it between
// the channels of a chromatic medium).
fn regular_tracking_tau(m: MediumGpu, r: Ray, t0: f32, t1: f32, lookups: ptr<function, u32>) -> f32 {
    var tau = 0.0;
    var dda = dda_new(r, 1.0, m.dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        *lookups += 1u;
        tau += classify(m, fetch(m, s.cell.x, s.cell.y, s.cell.z)) * (s.t1 - s.t0);
    }
    return tau * m.scale;
}

// fogbank_estimators::distance::analytic_trilinear::sample_tracked: exact
// free flight through the trilinear field (Lin et al. 2021 Fig. 12's
// full-resolution column): walk the dual cells summing their exact optical
// depths until the sum reaches −ln(1 − u), then solve ∫_a^x σ = rest in that
// cell (a monotone quartic) by Newton's method safeguarded by bisection.
// Its density σ_t(t)·exp(−τ(t)) has a closed form, as reuse needs.

// x in [a, b] with ∫_a^x σ = rest, given ∫_a^b σ = total ≥ rest. f32: the
// bracket stops at 1e-6 of the cell segment (the CPU's f64 at 1e-13).
fn dual_invert(d: ptr<function, DualCell>, o: vec3<f32>, dir: vec3<f32>, a: f32, b: f32,
               rest: f32, total: f32) -> f32 {
    var lo = a;
    var hi = b;
    var x = a + (b - a) * clamp(rest / total, 0.0, 1.0);
    for (var i = 0u; i < 48u; i++) {
        let f = dual_integral(d, o, dir, a, x) - rest;
        if (f == 0.0) {
            return x;
        }
        if (f > 0.0) {
            hi = x;
        } else {
            lo = x;
        }
        if (hi - lo <= 1e-6 * (b - a)) {
            break;
        }
        let slope = dual_value(d, o, dir, x);
        let newton = x - f / slope;
        if (slope > 0.0 && newton > lo && newton < hi) {
            x = newton;
        } else {
            x = 0.5 * (lo + hi);
        }
    }
    return x;
}

// The collision (t < 0: none) of the index-space ray r in [t0, t1] for the
// uniform number u, with σ_t there and the optical depth to it (whole
// range on escape), in the medium's scaled units.
fn trilinear_flight(m: MediumGpu, r: Ray, t0: f32, t1: f32, u: f32,
                    lookups: ptr<function, u32>) -> vec3<f32> {
    let target_tau = -log(1.0 - u);
    let target_unscaled = target_tau / m.scale;
    var shifted = r;
    shifted.o = r.o + vec3<f32>(0.5);
    var tau = 0.0;
    // Zero super-voxels hold no collision (occupied.wgsl).
    var spans = spans_new(m, r, t0, t1);
    var span: vec2<f32>;
    while (spans_next(&spans, m, true, &span)) {
        var dda = dda_new(shifted, 1.0, m.dims + vec3<u32>(1u), span.x, span.y);
        var s: DdaStep;
        while (dda_next(&dda, &s)) {
            if (s.t1 <= s.t0) {
                continue;
            }
            *lookups += 1u;
            var cell = dual_cell(m, s.cell);
            let d_tau = dual_integral(&cell, shifted.o, shifted.d, s.t0, s.t1);
            if (tau + d_tau >= target_unscaled && d_tau > 0.0) {
                let t = clamp(dual_invert(&cell, shifted.o, shifted.d, s.t0, s.t1,
                                          target_unscaled - tau, d_tau), s.t0, s.t1);
                return vec3<f32>(t, m.scale * dual_value(&cell, shifted.o, shifted.d, t), target_tau);
            }
            tau += d_tau;
        }
    }
    return vec3<f32>(NO_HIT, 0.0, tau * m.scale);
}

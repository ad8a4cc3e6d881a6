// fogbank_estimators::analytic_trilinear: the optical depth of the
// trilinear interpolant, exact per dual cell (a cubic in t) by two-point
// Gauss–Legendre.

const GL_NODE: f32 = 0.5773502691896258;

fn analytic_trilinear(m: MediumGpu, r: Ray, t0: f32, t1: f32, lookups: ptr<function, u32>) -> f32 {
    var shifted = r;
    shifted.o = r.o + vec3<f32>(0.5);
    var tau = 0.0;
    var dda = dda_new(shifted, 1.0, m.dims + vec3<u32>(1u), t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let len = s.t1 - s.t0;
        if (len <= 0.0) {
            continue;
        }
        *lookups += 1u;
        let c = s.cell - vec3<i32>(1);
        let c000 = fetch(m, c.x, c.y, c.z);
        let c100 = fetch(m, c.x + 1, c.y, c.z);
        let c010 = fetch(m, c.x, c.y + 1, c.z);
        let c110 = fetch(m, c.x + 1, c.y + 1, c.z);
        let c001 = fetch(m, c.x, c.y, c.z + 1);
        let c101 = fetch(m, c.x + 1, c.y, c.z + 1);
        let c011 = fetch(m, c.x, c.y + 1, c.z + 1);
        let c111 = fetch(m, c.x + 1, c.y + 1, c.z + 1);
        let base = vec3<f32>(s.cell);
        let mid = 0.5 * (s.t0 + s.t1);
        let half_len = 0.5 * len;
        var sum = 0.0;
        for (var k = 0; k < 2; k++) {
            let t = mid + select(-1.0, 1.0, k == 1) * half_len * GL_NODE;
            // Relative to the cell corner, so the weights keep f32 precision
            // far from the index origin.
            let w = clamp(shifted.o - base + t * shifted.d, vec3<f32>(0.0), vec3<f32>(1.0));
            let x0 = c000 + w.x * (c100 - c000);
            let x1 = c010 + w.x * (c110 - c010);
            let x2 = c001 + w.x * (c101 - c001);
            let x3 = c011 + w.x * (c111 - c011);
            let y0 = x0 + w.y * (x1 - x0);
            let y1 = x2 + w.y * (x3 - x2);
            sum += y0 + w.z * (y1 - y0);
        }
        tau += sum * half_len;
    }
    return exp(-tau * m.scale);
}

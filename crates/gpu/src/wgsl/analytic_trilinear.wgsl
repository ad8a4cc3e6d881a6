// fogbank_estimators::analytic_trilinear: the optical depth of the
// trilinear interpolant, exact per dual cell (a cubic in t) by two-point
// Gauss–Legendre. The dual cell is the one definition the exact free-flight
// sampler (distance_trilinear.wgsl) shares.

const GL_NODE: f32 = 0.5773502691896258;

// analytic_trilinear::DualCell: the eight voxel values around dual cell c
// (which spans voxel centres c − 1 … c of the ray shifted by +½).
struct DualCell {
    c: array<f32, 8>,
    base: vec3<f32>,
}

fn dual_cell(m: MediumGpu, cell: vec3<i32>) -> DualCell {
    let c = cell - vec3<i32>(1);
    var d: DualCell;
    d.c[0] = fetch(m, c.x, c.y, c.z);
    d.c[1] = fetch(m, c.x + 1, c.y, c.z);
    d.c[2] = fetch(m, c.x, c.y + 1, c.z);
    d.c[3] = fetch(m, c.x + 1, c.y + 1, c.z);
    d.c[4] = fetch(m, c.x, c.y, c.z + 1);
    d.c[5] = fetch(m, c.x + 1, c.y, c.z + 1);
    d.c[6] = fetch(m, c.x, c.y + 1, c.z + 1);
    d.c[7] = fetch(m, c.x + 1, c.y + 1, c.z + 1);
    d.base = vec3<f32>(cell);
    return d;
}

// DualCell::value at parameter t of the shifted ray o + t d. Relative to
// the cell corner, so the weights keep f32 precision far from the origin.
fn dual_value(d: ptr<function, DualCell>, o: vec3<f32>, dir: vec3<f32>, t: f32) -> f32 {
    let w = clamp(o - (*d).base + t * dir, vec3<f32>(0.0), vec3<f32>(1.0));
    let x0 = (*d).c[0] + w.x * ((*d).c[1] - (*d).c[0]);
    let x1 = (*d).c[2] + w.x * ((*d).c[3] - (*d).c[2]);
    let x2 = (*d).c[4] + w.x * ((*d).c[5] - (*d).c[4]);
    let x3 = (*d).c[6] + w.x * ((*d).c[7] - (*d).c[6]);
    let y0 = x0 + w.y * (x1 - x0);
    let y1 = x2 + w.y * (x3 - x2);
    return y0 + w.z * (y1 - y0);
}

// DualCell::integral over [a, b]: exact for the cubic.
fn dual_integral(d: ptr<function, DualCell>, o: vec3<f32>, dir: vec3<f32>, a: f32, b: f32) -> f32 {
    let mid = 0.5 * (a + b);
    let half_len = 0.5 * (b - a);
    return (dual_value(d, o, dir, mid - half_len * GL_NODE)
        + dual_value(d, o, dir, mid + half_len * GL_NODE)) * half_len;
}

fn analytic_trilinear(m: MediumGpu, r: Ray, t0: f32, t1: f32, lookups: ptr<function, u32>) -> f32 {
    return exp(-analytic_trilinear_tau(m, r, t0, t1, lookups));
}

// analytic_trilinear::optical_depth: the exact τ.
fn analytic_trilinear_tau(m: MediumGpu, r: Ray, t0: f32, t1: f32, lookups: ptr<function, u32>) -> f32 {
    var shifted = r;
    shifted.o = r.o + vec3<f32>(0.5);
    var tau = 0.0;
    // Zero super-voxels add nothing (occupied.wgsl).
    var spans = spans_new(m, r, t0, t1);
    var span: vec2<f32>;
    while (spans_next(&spans, m, true, &span)) {
        var dda = dda_new(shifted, 1.0, m.dims + vec3<u32>(1u), span.x, span.y);
        var s: DdaStep;
        while (dda_next(&dda, &s)) {
            if (s.t1 - s.t0 <= 0.0) {
                continue;
            }
            *lookups += 1u;
            var cell = dual_cell(m, s.cell);
            tau += dual_integral(&cell, shifted.o, shifted.d, s.t0, s.t1);
        }
    }
    return tau * m.scale;
}

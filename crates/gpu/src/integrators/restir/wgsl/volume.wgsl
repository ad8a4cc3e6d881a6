// fogbank_render::integrators::restir::volume on the GPU: σ_t of the
// full-resolution trilinear field, regular tracking through a conservative
// mip with its closed-form pdf (Lin et al. 2021 Eq. 27–28), and T̃ by deterministic
// midpoint marching (§4.3, §5.1). Record 0 of `media` is the scene's medium.

// volume::sigma_t: the trilinear σ_t at world point p, 0 outside the box.
fn restir_sigma_t(p: vec3<f32>) -> f32 {
    let m = media[0];
    let o = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
    if (any(q < vec3<f32>(0.0)) || any(q > vec3<f32>(m.dims))) {
        return 0.0;
    }
    return m.scale * max(trilinear(m, q), 0.0);
}

// TrackedFlight: t < 0 on escape; sigma_t at t; tau to t (whole ray on escape).
struct Flight {
    t: f32,
    sigma_t: f32,
    tau: f32,
}

// volume::track: regular tracking (regular_tracking::sample_tracked)
// through the nearest-filtered mip record `mi` — the exact optical depth
// inverted voxel by voxel — or, for record 0 (the scene's medium, mip
// level 0), exact free flight through its trilinear field.
fn restir_track(mi: u32, world: Ray, t_max: f32, rng: ptr<function, Pcg32>,
                lookups: ptr<function, u32>) -> Flight {
    let m = media[mi];
    var r: Ray;
    let range = to_index(m, world, t_max, &r);
    let u = pcg32_next_f32(rng);
    if (range.z == 0.0) {
        return Flight(NO_HIT, 0.0, 0.0);
    }
    if (mi == 0u) {
        let f = trilinear_flight(m, r, range.x, range.y, u, lookups);
        return Flight(f.x, f.y, f.z);
    }
    let f = regular_flight(m, r, range.x, range.y, u, lookups);
    return Flight(f.x, f.y, f.z);
}

// deterministic_marching::optical_depth: trilinear midpoints on a fixed
// grid of `step` index units from t0; no random numbers.
fn marched_tau(m: MediumGpu, r: Ray, t0: f32, t1: f32, step: f32, lookups: ptr<function, u32>) -> f32 {
    let speed = length(r.d);
    if (!(t1 > t0) || step <= 0.0 || speed <= 0.0) {
        return 0.0;
    }
    let dt = step / speed;
    let n = u32(max(ceil((t1 - t0) / dt), 1.0));
    var tau = 0.0;
    // Only steps that reach a non-zero super-voxel (occupied.wgsl); the
    // others would add exact zeros. `next` keeps a step shared by two spans
    // from counting twice.
    var next = 0u;
    var spans = spans_new(m, r, t0, t1);
    var span: vec2<f32>;
    while (spans_next(&spans, m, true, &span)) {
        let first = max(u32(max(floor((span.x - t0) / dt), 0.0)), next);
        let end = min(u32(max(floor((span.y - t0) / dt), 0.0)) + 1u, n);
        for (var i = first; i < end; i++) {
            let lo = t0 + f32(i) * dt;
            let hi = min(lo + dt, t1);
            tau += trilinear(m, ray_at(r, 0.5 * (lo + hi))) * (hi - lo);
            *lookups += 1u;
        }
        next = max(next, end);
    }
    return tau * m.scale;
}

const SQRT3: f32 = 1.7320508;

// SegmentT::Marched: T̃ of [0, t_max] along the world ray through record
// `mi`, marched in steps of `step` voxel diagonals.
fn marched_t(mi: u32, step: f32, world: Ray, t_max: f32, lookups: ptr<function, u32>) -> f32 {
    let m = media[mi];
    var r: Ray;
    let range = to_index(m, world, t_max, &r);
    if (range.z == 0.0) {
        return 1.0;
    }
    return exp(-marched_tau(m, r, range.x, range.y, step * SQRT3, lookups));
}

// SegmentT::Exact / Estimated: the shading estimator ESTIMATOR on the
// full-resolution medium (analytic_trilinear gives the exact T).
fn shading_t(world: Ray, t_max: f32, rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    let m = media[0];
    var r: Ray;
    let range = to_index(m, world, t_max, &r);
    if (range.z == 0.0) {
        return 1.0;
    }
    return estimate(m, r, range.x, range.y, rng, lookups);
}

fn segment_t(mode: u32, world: Ray, t_max: f32, rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    if (mode == MODE_TARGET) {
        return marched_t(rp.reuse_record, rp.reuse_step, world, t_max, lookups);
    }
    return shading_t(world, t_max, rng, lookups);
}

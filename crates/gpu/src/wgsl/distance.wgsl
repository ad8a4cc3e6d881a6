// fogbank_estimators::distance: free-flight samplers. Each returns the
// collision's ray parameter, or −1 when the ray leaves [t0, t1].

const NO_HIT: f32 = -1.0;

// distance::delta_tracking::track and delta_tracking_ratio::sample: delta
// tracking over super-voxel majorants that also returns the σ_t read at the
// collision and the ratio-tracking product of its null events. The one
// delta-tracking loop: free-flight sampling, track-length and point_mis use it.
struct TrackedFlight {
    t: f32,
    sigma_t: f32,
    ratio: f32,
}

fn delta_tracking_ratio(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                        rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> TrackedFlight {
    var out = TrackedFlight(NO_HIT, 0.0, 1.0);
    var dda = dda_new(r, m.sv_size, m.sv_dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let sigma_maj = supervoxel(m, s.cell).y;
        if (sigma_maj <= 0.0) {
            continue;
        }
        var t = s.t0;
        loop {
            t += -log(1.0 - pcg32_next_f32(rng)) / sigma_maj;
            if (t >= s.t1) {
                break;
            }
            let sigma_t = sigma_t_at(m, ray_at(r, t), rng, lookups);
            if (pcg32_next_f32(rng) * sigma_maj < sigma_t) {
                out.t = t;
                out.sigma_t = sigma_t;
                return out;
            }
            out.ratio *= null_probability(sigma_t, sigma_maj);
        }
    }
    return out;
}

// distance::delta_tracking::sample.
fn delta_tracking_sample(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                         rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    return delta_tracking_ratio(m, r, t0, t1, rng, lookups).t;
}

// Decomposition tracking (Kutz et al. 2017): the super-voxel minimum as a
// homogeneous control, delta tracking of the residual.
fn decomposition_tracking_sample(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                                 rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var dda = dda_new(r, m.sv_size, m.sv_dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let sv = supervoxel(m, s.cell);
        if (sv.y <= 0.0) {
            continue;
        }
        var t_control = F32_INF;
        if (sv.x > 0.0) {
            t_control = s.t0 + -log(1.0 - pcg32_next_f32(rng)) / sv.x;
        }
        let limit = min(t_control, s.t1);
        let sigma_r = sv.y - sv.x;
        if (sigma_r > 0.0) {
            var t = s.t0;
            loop {
                t += -log(1.0 - pcg32_next_f32(rng)) / sigma_r;
                if (t >= limit) {
                    break;
                }
                let sigma_t = sigma_t_at(m, ray_at(r, t), rng, lookups);
                if (pcg32_next_f32(rng) * sigma_r < sigma_t - sv.x) {
                    return t;
                }
            }
        }
        if (t_control < s.t1) {
            return t_control;
        }
    }
    return NO_HIT;
}

// Regular tracking: invert the exact optical depth of the nearest-filtered
// grid voxel by voxel, for the uniform number u (TrackedFlight): (t or
// NO_HIT, σ_t there, τ to it or over the whole range on escape).
fn regular_flight(m: MediumGpu, r: Ray, t0: f32, t1: f32, u: f32,
                  lookups: ptr<function, u32>) -> vec3<f32> {
    let tau_target = -log(1.0 - u);
    var tau = 0.0;
    // Zero super-voxels hold no collision (occupied.wgsl).
    var spans = spans_new(m, r, t0, t1);
    var span: vec2<f32>;
    while (spans_next(&spans, m, false, &span)) {
        var dda = dda_new(r, 1.0, m.dims, span.x, span.y);
        var s: DdaStep;
        while (dda_next(&dda, &s)) {
            *lookups += 1u;
            let sigma_t = m.scale * classify(m, fetch(m, s.cell.x, s.cell.y, s.cell.z));
            let d = sigma_t * (s.t1 - s.t0);
            if (tau + d >= tau_target && sigma_t > 0.0) {
                return vec3<f32>(clamp(s.t0 + (tau_target - tau) / sigma_t, s.t0, s.t1), sigma_t, tau_target);
            }
            tau += d;
        }
    }
    return vec3<f32>(NO_HIT, 0.0, tau);
}

fn regular_tracking_sample(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                           rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    return regular_flight(m, r, t0, t1, pcg32_next_f32(rng), lookups).x;
}

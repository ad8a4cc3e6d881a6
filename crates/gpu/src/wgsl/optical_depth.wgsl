// fogbank_estimators::optical_depth: Peters 2025 Alg. 2 (total importance F
// and the tight segment) and Alg. 1 (m ≤ 9 interleaved optical-depth
// estimates, each with its own CDF cursor), importance of Eq. 5 with the
// super-voxel minimum as control variate, or the mean without it.

const MAX_ESTIMATES: u32 = 9u;

struct Prepared {
    total: f32,
    t_min: f32,
    t_max: f32,
}

// (importance p, control μ_c) of a super-voxel (min, max, mean, importance).
fn importance_of(sv: vec4<f32>, mean_importance: bool) -> vec2<f32> {
    if (mean_importance) {
        return vec2<f32>(sv.z, 0.0);
    }
    return vec2<f32>(sv.w, sv.x);
}

// Peters 2025, Alg. 2.
fn od_prepare(m: MediumGpu, r: Ray, t0: f32, t1: f32, mean_importance: bool) -> Prepared {
    var out = Prepared(0.0, t1, t0);
    var dda = dda_new(r, m.sv_size, m.sv_dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let p = importance_of(supervoxel(m, s.cell), mean_importance).x;
        if (p > 0.0) {
            out.total += (s.t1 - s.t0) * p;
            out.t_min = min(out.t_min, s.t0);
            out.t_max = max(out.t_max, s.t1);
        }
    }
    return out;
}

fn argmin_cursor(c: ptr<function, array<f32, 9>>, count: u32) -> u32 {
    var b = 0u;
    for (var k = 1u; k < count; k++) {
        if ((*c)[k] < (*c)[b]) {
            b = k;
        }
    }
    return b;
}

// Peters 2025, Alg. 1: `count` estimates into `out`, one stratum of F per
// f_delta, stratified (floor(I) + 1 + u) or uniformly (I + 1) jittered.
fn od_estimates(m: MediumGpu, r: Ray, prep: Prepared, f_delta: f32, mean_importance: bool,
                uniform_jitter: bool, count: u32, rng: ptr<function, Pcg32>,
                lookups: ptr<function, u32>, out: ptr<function, array<f32, 9>>) {
    let n = min(count, MAX_ESTIMATES);
    for (var k = 0u; k < MAX_ESTIMATES; k++) {
        (*out)[k] = 0.0;
    }
    if (n == 0u || prep.total <= 0.0 || f_delta <= 0.0) {
        return;
    }
    var cursor: array<f32, 9>;
    for (var k = 0u; k < MAX_ESTIMATES; k++) {
        cursor[k] = F32_INF;
    }
    for (var k = 0u; k < n; k++) {
        cursor[k] = pcg32_next_f32(rng);
    }
    var j = argmin_cursor(&cursor, n);
    var f = 0.0;
    var tau_c = 0.0;
    var dda = dda_new(r, m.sv_size, m.sv_dims, prep.t_min, prep.t_max);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let pc = importance_of(supervoxel(m, s.cell), mean_importance);
        let p = pc.x;
        let len = s.t1 - s.t0;
        tau_c += len * pc.y;
        if (p <= 0.0) {
            continue;
        }
        f += len * p;
        while (f_delta * cursor[j] < f) {
            let t = clamp(s.t1 - (f - f_delta * cursor[j]) / p, s.t0, s.t1);
            let sigma_t = sigma_t_at(m, ray_at(r, t), rng, lookups);
            (*out)[j] += (sigma_t - pc.y) / p;
            if (uniform_jitter) {
                cursor[j] = cursor[j] + 1.0;
            } else {
                cursor[j] = floor(cursor[j]) + 1.0 + pcg32_next_f32(rng);
            }
            j = argmin_cursor(&cursor, n);
        }
    }
    for (var k = 0u; k < n; k++) {
        (*out)[k] = f_delta * (*out)[k] + tau_c;
    }
}

// jackknife::optical_depths: Alg. 2 then Alg. 1 with F/N per stratum, or a
// fixed step when `step` > 0.
fn optical_depths(m: MediumGpu, r: Ray, t0: f32, t1: f32, samples: u32, step: f32,
                  mean_importance: bool, uniform_jitter: bool, count: u32,
                  rng: ptr<function, Pcg32>, lookups: ptr<function, u32>,
                  out: ptr<function, array<f32, 9>>) {
    for (var k = 0u; k < MAX_ESTIMATES; k++) {
        (*out)[k] = 0.0;
    }
    let prep = od_prepare(m, r, t0, t1, mean_importance);
    if (prep.total > 0.0) {
        var f_delta = prep.total / f32(max(samples, 1u));
        if (step > 0.0) {
            f_delta = max(step, 1e-6);
        }
        od_estimates(m, r, prep, f_delta, mean_importance, uniform_jitter, count, rng, lookups, out);
    }
}

// fogbank_estimators::null_collisions::walk for the estimators that share
// it: track-length (stop at the first real collision) and ratio tracking
// (multiply by 1 − μ/μ̄ at each event) over super-voxel majorants, and
// residual ratio tracking (control μ_c per super-voxel, ratio tracking of
// the residual with majorant max(μ_max − μ_c, μ_c − μ_min)); both play
// Russian roulette once the running estimate falls below `roulette` (0:
// never; fogbank_estimators::roulette).

const WALK_RATIO: u32 = 0u;
const WALK_RESIDUAL: u32 = 1u;

fn null_collision_walk(m: MediumGpu, r: Ray, t0: f32, t1: f32, mode: u32, roulette: f32,
                       rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var tr = 1.0;
    var tau_c = 0.0;
    // Super-voxel diagonal in ray-parameter units (residual control).
    let diagonal = m.sv_size * sqrt(3.0) / max(length(r.d), 1.1754944e-38);
    var dda = dda_new(r, m.sv_size, m.sv_dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let rate = walk_rate(m, s, mode, diagonal, &tau_c);
        let sigma_maj = rate.x;
        let sigma_c = rate.y;
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
            if (mode == WALK_RESIDUAL) {
                tr *= 1.0 - (sigma_t - sigma_c) / sigma_maj;
            } else {
                tr *= null_probability(sigma_t, sigma_maj);
                if (tr == 0.0) {
                    return 0.0;
                }
            }
            if (roulette > 0.0) {
                var running = abs(tr);
                if (mode == WALK_RESIDUAL) {
                    running *= exp(-tau_c);
                }
                let q = running / roulette;
                if (q < 1.0) {
                    if (!(q > 0.0) || pcg32_next_f32(rng) >= q) {
                        return 0.0;
                    }
                    tr /= q;
                }
            }
        }
    }
    if (mode == WALK_RESIDUAL) {
        return exp(-tau_c) * tr;
    }
    return tr;
}

// residual_ratio_tracking::control_extinction: a control between the
// super-voxel's minimum and mean that keeps the residual majorant small.
// Tracking::rate of the walk's DDA step s: (majorant, control σ_c); for
// residual tracking the residual majorant, with the control's optical
// depth added to *tau_c (a step without medium: majorant 0, no control).
fn walk_rate(m: MediumGpu, s: DdaStep, mode: u32, diagonal: f32,
             tau_c: ptr<function, f32>) -> vec2<f32> {
    let sv = supervoxel(m, s.cell);
    if (mode != WALK_RESIDUAL) {
        return vec2<f32>(sv.y, 0.0);
    }
    if (sv.y <= 0.0) {
        return vec2<f32>(0.0);
    }
    let sigma_c = control_extinction(sv, diagonal);
    *tau_c += (s.t1 - s.t0) * sigma_c;
    return vec2<f32>(max(sv.y - sigma_c, sigma_c - sv.x), sigma_c);
}

fn control_extinction(sv: vec4<f32>, d: f32) -> f32 {
    let delta = sv.y - sv.x;
    if (delta <= 0.0) {
        return sv.x;
    }
    let c = sv.x + delta * (exp2(1.0 / (d * delta)) - 1.0);
    return min(sv.z, max(c, sv.x));
}

// null_collisions::walk as ratio_tracking::transmittance_scaled and
// residual_ratio_tracking::transmittance_scaled: every channel of a
// chromatic medium (extinction k_c times m's, k_c ≤ 1) weighted at the
// same tentative collisions of m's majorant. A copy of the walk above
// rather than that walk with k = 1: the scalar walk is the hot loop of
// every kernel, and this one is compiled only with chromatic media
// (INTEGRATOR_CHROMATIC).
fn null_collision_walk_rgb(m: MediumGpu, r: Ray, t0: f32, t1: f32, mode: u32, k: vec3<f32>,
                           roulette: f32, rng: ptr<function, Pcg32>,
                           lookups: ptr<function, u32>) -> vec3<f32> {
    var tr = vec3<f32>(1.0);
    var tau_c = 0.0;
    let diagonal = m.sv_size * sqrt(3.0) / max(length(r.d), 1.1754944e-38);
    var dda = dda_new(r, m.sv_size, m.sv_dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let rate = walk_rate(m, s, mode, diagonal, &tau_c);
        let sigma_maj = rate.x;
        let sigma_c = rate.y;
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
            if (mode == WALK_RESIDUAL) {
                tr *= vec3<f32>(1.0) - k * ((sigma_t - sigma_c) / sigma_maj);
            } else {
                tr *= vec3<f32>(null_probability(k.x * sigma_t, sigma_maj),
                                null_probability(k.y * sigma_t, sigma_maj),
                                null_probability(k.z * sigma_t, sigma_maj));
                if (all(tr == vec3<f32>(0.0))) {
                    return tr;
                }
            }
            if (roulette > 0.0) {
                var running = abs(tr);
                if (mode == WALK_RESIDUAL) {
                    running *= exp(-k * tau_c);
                }
                let q = max(running.x, max(running.y, running.z)) / roulette;
                if (q < 1.0) {
                    if (!(q > 0.0) || pcg32_next_f32(rng) >= q) {
                        return vec3<f32>(0.0);
                    }
                    tr /= q;
                }
            }
        }
    }
    if (mode == WALK_RESIDUAL) {
        return exp(-k * tau_c) * tr;
    }
    return tr;
}

// fogbank_estimators::distance::ray_marching (Hansen 2025 §2.4–§2.5): the
// thesis's fixed-step ray marching, one jitter per ray; free flight solves
// inside the step where τ passes −ln(1 − ξ). `dt` is in the ray parameter.

const MARCH_MAX_STEPS: u32 = 1048576u;

// ray_marching::steps: (step count, step), at most MARCH_MAX_STEPS steps.
fn march_steps(t0: f32, t1: f32, dt_in: f32) -> vec2<f32> {
    let len = t1 - t0;
    let dt = max(dt_in, len / f32(MARCH_MAX_STEPS));
    if (!(len > 0.0 && dt > 0.0)) {
        return vec2<f32>(0.0, dt);
    }
    return vec2<f32>(f32(clamp(u32(ceil(len / dt)), 1u, MARCH_MAX_STEPS)), dt);
}

// Step j of the grid (step dt, one jitter u per ray): its ends (x, y) and
// the point read, a + u·(b − a) (z).
fn march_step(t0: f32, t1: f32, dt: f32, j: u32, u: f32) -> vec3<f32> {
    let a = t0 + f32(j) * dt;
    let b = min(a + dt, t1);
    return vec3<f32>(a, b, a + u * (b - a));
}

fn march_sample(m: MediumGpu, r: Ray, t0: f32, t1: f32, dt_in: f32,
                rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    let target_tau = -log(1.0 - pcg32_next_f32(rng));
    let u = pcg32_next_f32(rng);
    let s = march_steps(t0, t1, dt_in);
    var tau = 0.0;
    for (var j = 0u; j < u32(s.x); j++) {
        let step = march_step(t0, t1, s.y, j, u);
        let sigma = sigma_t_at(m, ray_at(r, step.z), rng, lookups);
        let d = sigma * (step.y - step.x);
        if (tau + d >= target_tau && sigma > 0.0) {
            return clamp(step.x + (target_tau - tau) / sigma, step.x, step.y);
        }
        tau += d;
    }
    return NO_HIT;
}

fn march_transmittance(m: MediumGpu, r: Ray, t0: f32, t1: f32, dt_in: f32,
                       rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    let u = pcg32_next_f32(rng);
    let s = march_steps(t0, t1, dt_in);
    var tau = 0.0;
    for (var j = 0u; j < u32(s.x); j++) {
        let step = march_step(t0, t1, s.y, j, u);
        tau += sigma_t_at(m, ray_at(r, step.z), rng, lookups) * (step.y - step.x);
    }
    return exp(-tau);
}

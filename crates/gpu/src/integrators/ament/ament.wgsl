// Integrator `ament` (integrators/ament.rs): the ray-marched extinction
// optimisation of Ament, Zirr and Dachsbacher 2017, Lerzer and Dachsbacher 2025's baseline.
// Each ray is marched twice with a fixed step — once for Σ g² (its
// importance), once to composite with μ'_i = μ_i · p / (p + (1 − g_i)^{2λ}
// h_i), h_i = r Σ_{j<i} g_j² w + q Σ_{j>i} g_j² w (w = 1 as printed, Δx
// normalised) — since the CPU's per-ray sample arrays do not fit an
// invocation; single scattering, a likewise optimised shadow ray marched
// to every (delta) light.

// The world step: Δx in [−1, 1]³ units.
fn march_dt() -> f32 {
    return vo.step / vo.unit;
}

// Ament::march: samples at s0 + (i + start) Δx while inside [s0, s1].
fn march_count(s0: f32, s1: f32, start: f32) -> u32 {
    return u32(max(ceil((s1 - s0) / march_dt() - start), 0.0));
}

// g² w of the importance at a sample (w = Δx unless printed).
fn importance_weight(g: f32) -> f32 {
    if (vo_flag(VISOPT_PRINTED)) {
        return g * g;
    }
    return g * g * vo.step;
}

// Σ_j g_j² w over a march (0 when not optimising).
fn march_importance(m: MediumGpu, ray: Ray, s0: f32, n: u32, start: f32) -> f32 {
    var total = 0.0;
    if (!vo_flag(VISOPT_OPTIMISE)) {
        return total;
    }
    for (var i = 0u; i < n; i++) {
        total += ament_sample(m, ray_at(ray, s0 + (f32(i) + start) * march_dt())).z;
    }
    return total;
}

// (σ_t, g, g² w) at world point p (g = 0 when not optimising).
fn ament_sample(m: MediumGpu, p: vec3<f32>) -> vec3<f32> {
    let sigma = sigma_smooth(m, p);
    if (!vo_flag(VISOPT_OPTIMISE)) {
        return vec3<f32>(sigma, 0.0, 0.0);
    }
    let g = importance_at(p, sigma);
    return vec3<f32>(sigma, g, importance_weight(g));
}

// μ'_i of a sample with μ_t = sigma, importance g and Σ g² w before (in
// the direction of the viewer) and after it; μ itself when not optimising.
fn ament_mu(sigma: f32, g: f32, before: f32, after: f32) -> f32 {
    if (!vo_flag(VISOPT_OPTIMISE)) {
        return sigma;
    }
    return sigma * mu_factor(g, vo.r * before + vo.q * after);
}

// Ament::shadow: optimised transmittance from p toward a light `distance`
// away; the light plays the camera, so "before" is the light's side.
fn ament_shadow(m: MediumGpu, p: vec3<f32>, wi: vec3<f32>, distance: f32) -> f32 {
    var world: Ray;
    world.o = p;
    world.d = wi;
    if (!visible(world, distance)) {
        return 0.0;
    }
    var r: Ray;
    let range = to_index(m, world, distance, &r);
    if (range.z == 0.0) {
        return 1.0;
    }
    let n = march_count(range.x, range.y, 0.5);
    let total = march_importance(m, world, range.x, n, 0.5);
    var before = 0.0;
    var tau = 0.0;
    for (var j = 0u; j < n; j++) {
        let i = n - 1u - j;
        let x = ament_sample(m, ray_at(world, range.x + (f32(i) + 0.5) * march_dt()));
        tau += ament_mu(x.x, x.y, before, max(total - before - x.z, 0.0)) * march_dt();
        before += x.z;
    }
    return exp(-tau);
}

// shared::next_event::delta_lights: Σ L_l f(ω_l) T toward every light.
fn ament_lights(m: MediumGpu, p: vec3<f32>, d: vec3<f32>, lookups: ptr<function, u32>) -> vec3<f32> {
    var lit = vec3<f32>(0.0);
    for (var i = 0u; i < env.light_count; i++) {
        let ls = light_sample_li(lights[i], p, 0.5, 0.5);
        if (!ls.valid) {
            continue;
        }
        let f = dvr_phase(p, d, ls.wi);
        if (f > 0.0) {
            // The CPU counts one lookup per shadow march.
            *lookups += 1u;
            lit += ls.radiance * f * ament_shadow(m, p, ls.wi, ls.distance);
        }
    }
    return lit;
}

fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
    let ray = primary_ray(x, y, pixel, sample);
    let m = media[0];
    var r: Ray;
    // Marched up to the first surface (occluders.wgsl).
    let range = to_index_from_camera(m, ray, first_surface(ray), &r);
    if (range.z == 0.0) {
        return vec3<f32>(0.0);
    }
    var start = 0.5;
    if (vo_flag(VISOPT_JITTER)) {
        start = pcg32_next_f32(&rng);
    }
    let n = march_count(range.x, range.y, start);
    let total = march_importance(m, ray, range.x, n, start);
    *lookups += n;
    var transmittance = 1.0;
    var radiance = vec3<f32>(0.0);
    var before = 0.0;
    for (var i = 0u; i < n; i++) {
        let p = ray_at(ray, range.x + (f32(i) + start) * march_dt());
        let x = ament_sample(m, p);
        let mu = ament_mu(x.x, x.y, before, max(total - before - x.z, 0.0));
        before += x.z;
        let alpha = 1.0 - exp(-mu * march_dt());
        if (alpha <= 0.0) {
            continue;
        }
        let albedo = albedo_at(0u, p);
        let lit = ament_lights(m, p, ray.d, lookups);
        radiance += transmittance * alpha * (emitted(0u, p, albedo) + albedo * lit);
        transmittance *= 1.0 - alpha;
        if (transmittance < 1e-4) {
            break;
        }
    }
    return radiance;
}

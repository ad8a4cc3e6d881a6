// Integrators `direct` and `volpath` (direct = volpath with max_depth 1),
// mirroring integrators/volpath.rs, next_event.rs and media.rs sample for
// sample: free-flight sampling across media, next-event estimation toward
// one light chosen by power with the transmittance estimator ESTIMATOR,
// environments MIS-combined with phase sampling (at the last vertex the
// phase-sampled direction's transmittance is estimated instead of traced),
// Russian roulette on the throughput after rr_depth bounces. With
// INTEGRATOR_LIGHT_ONLY (volpath's restir_baseline preset, seed 002 §6):
// light sampling only, no phase-sampled escape, roulette by albedo.

fn light_only() -> bool {
    return (INTEGRATOR_FLAGS & INTEGRATOR_LIGHT_ONLY) != 0u;
}


// tracking::sampler_flight: fogbank's unbiased free-flight samplers.
fn unbiased_flight(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                   rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    // Lookups counted from 0 per call, as on the CPU (see `estimate`).
    var count = 0u;
    let t = unbiased_flight_with(m, r, t0, t1, rng, &count);
    *lookups += count;
    return t;
}

fn unbiased_flight_with(m: MediumGpu, r: Ray, t0: f32, t1: f32,
                        rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    switch SAMPLER {
        case SAMPLER_DELTA_TRACKING: {
            return delta_tracking_sample(m, r, t0, t1, rng, lookups);
        }
        case SAMPLER_DECOMPOSITION_TRACKING: {
            return decomposition_tracking_sample(m, r, t0, t1, rng, lookups);
        }
        case SAMPLER_REGULAR_TRACKING: {
            return regular_tracking_sample(m, r, t0, t1, rng, lookups);
        }
        default: {
            invalid_id();
            return NO_HIT;
        }
    }
}

// free_flight::next_collision for the ray leaving vertex `depth` (0: the
// view ray): (t, medium index) or t < 0.
fn next_collision(world: Ray, depth: u32, rng: ptr<function, Pcg32>,
                  lookups: ptr<function, u32>) -> vec2<f32> {
    let kind = flight_kind(depth);
    let from_camera = depth == 0u;
    var hit = vec2<f32>(NO_HIT, 0.0);
    for (var i = 0u; i < frame.media_count; i++) {
        let m = media[i];
        var t_max = F32_INF;
        if (hit.x >= 0.0) {
            t_max = hit.x;
        }
        var r: Ray;
        var range: vec3<f32>;
        if (from_camera) {
            range = to_index_from_camera(m, world, t_max, &r);
        } else {
            range = to_index(m, world, t_max, &r);
        }
        if (range.z == 0.0) {
            continue;
        }
        let t = tracked_flight(kind, i, m, r, range.x, range.y, rng, lookups);
        if (t >= 0.0) {
            hit = vec2<f32>(t, f32(i));
        }
    }
    return hit;
}

// free_flight::shadow_transmittance for NEE at scattering vertex `vertex`.
fn shadow(world: Ray, distance: f32, vertex: u32, rng: ptr<function, Pcg32>,
          lookups: ptr<function, u32>) -> f32 {
    let kind = shadow_kind(vertex);
    var tr = 1.0;
    for (var i = 0u; i < frame.media_count; i++) {
        let m = media[i];
        var r: Ray;
        let range = to_index(m, world, distance, &r);
        if (range.z != 0.0) {
            tr *= tracked_transmittance(kind, i, m, r, range.x, range.y, rng, lookups);
        }
    }
    return tr;
}

fn has_environment() -> bool {
    for (var i = 0u; i < env.light_count; i++) {
        if (is_environment(lights[i])) {
            return true;
        }
    }
    return false;
}

// next_event::light_sample
fn light_sample(p: vec3<f32>, d: vec3<f32>, g: f32, vertex: u32, rng: ptr<function, Pcg32>,
                lookups: ptr<function, u32>) -> vec3<f32> {
    // The CPU draws the selection number before finding there is no light.
    let u_pick = pcg32_next_f32(rng);
    if (env.pickable == 0u) {
        return vec3<f32>(0.0);
    }
    let li = pick_light(u_pick);
    let light = lights[li];
    let pmf = light.d.w;
    let u0 = pcg32_next_f32(rng);
    let u1 = pcg32_next_f32(rng);
    let ls = light_sample_li(light, p, u0, u1);
    if (!ls.valid) {
        return vec3<f32>(0.0);
    }
    let f = hg_eval(g, dot(d, ls.wi));
    if (f <= 0.0 || all(ls.radiance == vec3<f32>(0.0))) {
        return vec3<f32>(0.0);
    }
    var sr: Ray;
    sr.o = p;
    sr.d = ls.wi;
    let tr = shadow(sr, ls.distance, vertex, rng, lookups);
    if (ls.is_delta) {
        return ls.radiance * (f * tr / pmf);
    }
    if (light_only()) {
        return ls.radiance * (f * tr / (pmf * ls.pdf));
    }
    let light_pdf = pmf * ls.pdf;
    return ls.radiance * (f * tr * balance(light_pdf, f) / light_pdf);
}

// next_event::phase_sample_to_environment
fn phase_sample_to_environment(p: vec3<f32>, wi: vec3<f32>, phase_pdf: f32, vertex: u32,
                               rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> vec3<f32> {
    if (!has_environment()) {
        return vec3<f32>(0.0);
    }
    let le = escaped(wi, phase_pdf);
    if (all(le == vec3<f32>(0.0))) {
        return vec3<f32>(0.0);
    }
    var sr: Ray;
    sr.o = p;
    sr.d = wi;
    return le * shadow(sr, F32_INF, vertex, rng, lookups);
}

fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
    var ray = primary_ray(x, y, pixel, sample);
    var beta = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var phase_pdf = -1.0;
    for (var depth = 0u; depth < frame.max_depth; depth++) {
        let hit = next_collision(ray, depth, &rng, lookups);
        if (hit.x < 0.0) {
            if (!(light_only() && phase_pdf >= 0.0)) {
                radiance += beta * escaped(ray.d, phase_pdf);
            }
            break;
        }
        let mi = u32(hit.y);
        let sh = shading[mi];
        let p = ray.o + hit.x * ray.d;
        let albedo = albedo_at(mi, p);
        radiance += beta * emitted(mi, p, albedo);
        beta *= albedo;
        if (all(beta == vec3<f32>(0.0))) {
            break;
        }
        radiance += beta * light_sample(p, ray.d, sh.w, depth, &rng, lookups);
        let u0 = pcg32_next_f32(&rng);
        let u1 = pcg32_next_f32(&rng);
        let s = hg_sample(sh.w, -ray.d, u0, u1);
        if (depth + 1u == frame.max_depth) {
            if (light_only()) {
                break;
            }
            radiance += beta * phase_sample_to_environment(p, s.xyz, s.w, depth, &rng, lookups);
            break;
        }
        phase_pdf = s.w;
        ray.o = p;
        ray.d = s.xyz;
        if (depth + 1u >= frame.rr_depth) {
            var q = min(max(beta.x, max(beta.y, beta.z)), 1.0);
            if (light_only()) {
                q = min(max(albedo.x, max(albedo.y, albedo.z)), 1.0);
            }
            if (pcg32_next_f32(&rng) >= q) {
                break;
            }
            beta /= q;
        }
    }
    return radiance;
}


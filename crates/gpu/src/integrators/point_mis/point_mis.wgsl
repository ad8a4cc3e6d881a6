// Integrator `point_mis` (Peters 2025 §5, §6.2, Fig. 12), mirroring
// integrators/point_mis.rs sample for sample: single scattering from one
// point light (chosen by power) inside one medium, with free-flight,
// equiangular and the MIS strategies (Miller et al. 2019; Eq. 10 with naive
// or jackknife weights; Eq. 9 with jackknife weights).


// A pipeline constant, so the compiler drops the other strategies (all six
// inlined make one kernel that takes lavapipe half a minute to compile).
override STRATEGY: u32 = 0u;

// distance::equiangular (Kulla & Fajardo 2012) on the world ray.
fn equiangular_frame(r: Ray, light: vec3<f32>) -> vec2<f32> {
    let delta = dot(light - r.o, r.d);
    let d = max(length(r.o + delta * r.d - light), 1e-6);
    return vec2<f32>(delta, d);
}

fn equiangular_pdf_with(delta: f32, d: f32, theta_a: f32, theta_b: f32, t: f32) -> f32 {
    let span = theta_b - theta_a;
    if (span <= 0.0) {
        return 0.0;
    }
    return d / (span * (d * d + (t - delta) * (t - delta)));
}

fn equiangular_sample(r: Ray, light: vec3<f32>, a: f32, b: f32, u: f32) -> vec2<f32> {
    let f = equiangular_frame(r, light);
    let theta_a = atan((a - f.x) / f.y);
    let theta_b = atan((b - f.x) / f.y);
    let t = clamp(f.x + f.y * tan(theta_a + u * (theta_b - theta_a)), a, b);
    return vec2<f32>(t, equiangular_pdf_with(f.x, f.y, theta_a, theta_b, t));
}

fn equiangular_pdf(r: Ray, light: vec3<f32>, a: f32, b: f32, t: f32) -> f32 {
    if (t < a || t > b) {
        return 0.0;
    }
    let f = equiangular_frame(r, light);
    return equiangular_pdf_with(f.x, f.y, atan((a - f.x) / f.y), atan((b - f.x) / f.y), t);
}

// jackknife_function::mis_weight (Peters 2025 App. F): Re[(a T̃ + b)/(c T̃ + d)]
// with T̃ = e^{−X̄}(cos S − i sin S).
fn mis_weight(a: f32, b: f32, c: f32, d: f32, x0: f32, x1: f32) -> f32 {
    let xbar = 0.5 * (x0 + x1);
    let s = 0.5 * abs(x0 - x1);
    let e = exp(-xbar);
    let tre = e * cos(s);
    let tim = -e * sin(s);
    let nre = a * tre + b;
    let nim = a * tim;
    let dre = c * tre + d;
    let dim = c * tim;
    let den2 = dre * dre + dim * dim;
    if (den2 == 0.0) {
        return 0.0;
    }
    return (nre * dre + nim * dim) / den2;
}

struct Segment {
    world: Ray,
    index: Ray,
    a: f32,
    b: f32,
    light: vec3<f32>,
    intensity: vec3<f32>,
    g: f32,
    albedo: vec3<f32>,
}

// PointMis::in_scattered: α ρ I T_l / d², T_l by ESTIMATOR.
fn in_scattered(m: MediumGpu, s: Segment, t: f32, rng: ptr<function, Pcg32>,
                lookups: ptr<function, u32>) -> vec3<f32> {
    let p = ray_at(s.world, t);
    let to_light = s.light - p;
    let dist2 = dot(to_light, to_light);
    if (!(dist2 > 0.0 && dist2 < F32_INF)) {
        return vec3<f32>(0.0);
    }
    let dist = sqrt(dist2);
    let wi = to_light / dist;
    let f = hg_eval(s.g, dot(s.world.d, wi));
    var lr: Ray;
    lr.o = p;
    lr.d = wi;
    if (f <= 0.0 || !visible(lr, dist)) {
        return vec3<f32>(0.0);
    }
    var r: Ray;
    let range = to_index(m, lr, dist, &r);
    var tr = 1.0;
    if (range.z != 0.0) {
        tr = estimate(m, r, range.x, range.y, rng, lookups);
    }
    return albedo_at(0u, p) * s.intensity * (f * tr / dist2);
}

// PointMis::depths: two estimates of N (or one of 2N, repeated, naive).
fn depths(m: MediumGpu, s: Segment, t: f32, naive: bool, rng: ptr<function, Pcg32>,
          lookups: ptr<function, u32>) -> vec2<f32> {
    var x: array<f32, 9>;
    if (naive) {
        optical_depths(m, s.index, s.a, t, 2u * frame.mis_samples, 0.0, false, false, 1u, rng, lookups, &x);
        return vec2<f32>(x[0], x[0]);
    }
    optical_depths(m, s.index, s.a, t, frame.mis_samples, 0.0, false, false, 2u, rng, lookups, &x);
    return vec2<f32>(x[0], x[1]);
}

fn segment_sigma_t(m: MediumGpu, s: Segment, t: f32, rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    return sigma_t_at(m, ray_at(s.index, t), rng, lookups);
}

// One loop over the two distance samples (k = 0 free flight, k = 1
// equiangular), each adding c · L_s(t): the same random-number order as the
// CPU, with `depths` and `in_scattered` inlined once rather than per strategy.
fn point_mis_radiance(m: MediumGpu, s: Segment, rng: ptr<function, Pcg32>,
                      lookups: ptr<function, u32>) -> vec3<f32> {
    var total = vec3<f32>(0.0);
    if (STRATEGY >= STRATEGY_COUNT) {
        invalid_id();
        return total;
    }
    let jitter = m.filter_mode == 2u;
    let eq10 = STRATEGY == STRATEGY_MIS_NAIVE || STRATEGY == STRATEGY_MIS_JACKKNIFE_BIASED;
    let naive = STRATEGY == STRATEGY_MIS_NAIVE;
    var f = TrackedFlight(NO_HIT, 0.0, 1.0);
    var e = vec2<f32>(0.0, 0.0);
    if (eq10) {
        // Eq. 10 draws both distances before weighting either.
        f = delta_tracking_ratio(m, s.index, s.a, s.b, rng, lookups);
        e = equiangular_sample(s.world, s.light, s.a, s.b, pcg32_next_f32(rng));
    }
    for (var k = 0u; k < 2u; k++) {
        var t = 0.0;
        var c = 0.0;
        if (k == 0u) {
            if (STRATEGY == STRATEGY_EQUIANGULAR) {
                continue;
            }
            if (!eq10) {
                f = delta_tracking_ratio(m, s.index, s.a, s.b, rng, lookups);
            }
            if (f.t < 0.0) {
                continue;
            }
            t = f.t;
            if (STRATEGY == STRATEGY_FREE_FLIGHT) {
                c = 1.0;
            } else if (STRATEGY == STRATEGY_MIS_MILLER) {
                c = balance(f.sigma_t * f.ratio, equiangular_pdf(s.world, s.light, s.a, s.b, t));
                if (!(c > 0.0)) {
                    continue;
                }
            } else {
                var sigma_t = f.sigma_t;
                if (jitter) {
                    sigma_t = segment_sigma_t(m, s, t, rng, lookups);
                }
                if (eq10 && sigma_t <= 0.0) {
                    continue;
                }
                let x = depths(m, s, t, naive, rng, lookups);
                let p = equiangular_pdf(s.world, s.light, s.a, s.b, t);
                c = mis_weight(sigma_t, 0.0, sigma_t, p, x.x, x.y);
                if (c == 0.0 || !finite(c)) {
                    continue;
                }
            }
        } else {
            if (STRATEGY == STRATEGY_FREE_FLIGHT) {
                continue;
            }
            if (!eq10) {
                e = equiangular_sample(s.world, s.light, s.a, s.b, pcg32_next_f32(rng));
            }
            if (!(e.y > 0.0 && finite(e.y))) {
                continue;
            }
            t = e.x;
            let sigma_t_w = segment_sigma_t(m, s, t, rng, lookups);
            var sigma_t = sigma_t_w;
            if (STRATEGY == STRATEGY_MIS_JACKKNIFE && jitter) {
                sigma_t = segment_sigma_t(m, s, t, rng, lookups);
            }
            if (sigma_t <= 0.0) {
                continue;
            }
            if (STRATEGY == STRATEGY_EQUIANGULAR) {
                c = ratio_tracking(m, s.index, s.a, t, 0.0, rng, lookups) * sigma_t / e.y;
            } else if (STRATEGY == STRATEGY_MIS_MILLER) {
                let tr = ratio_tracking(m, s.index, s.a, t, 0.0, rng, lookups);
                c = balance(sigma_t * tr, e.y);
                if (c == 0.0) {
                    continue;
                }
            } else if (STRATEGY == STRATEGY_MIS_JACKKNIFE) {
                let x = depths(m, s, t, false, rng, lookups);
                let w0 = mis_weight(0.0, e.y, sigma_t_w, e.y, x.x, x.y);
                let tr = ratio_tracking(m, s.index, s.a, t, 0.0, rng, lookups);
                c = w0 * tr * sigma_t / e.y;
                if (c == 0.0 || !finite(c)) {
                    continue;
                }
            } else {
                let x = depths(m, s, t, naive, rng, lookups);
                c = mis_weight(sigma_t, 0.0, sigma_t, e.y, x.x, x.y);
                if (c == 0.0 || !finite(c)) {
                    continue;
                }
            }
        }
        total += in_scattered(m, s, t, rng, lookups) * c;
    }
    return total;
}

fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
    let world = primary_ray(x, y, pixel, sample);
    let m = media[0];
    var index: Ray;
    // The camera segment ends at the first surface (occluders.wgsl) or the
    // far clip plane.
    let range = to_index_from_camera(m, world, min(first_surface(world), camera_ray_end(world)), &index);
    if (range.z == 0.0) {
        return vec3<f32>(0.0);
    }
    let u_pick = pcg32_next_f32(&rng);
    if (env.pickable == 0u) {
        return vec3<f32>(0.0);
    }
    // Point lights only: no light BVH.
    let light = lights[pick_light(u_pick, false, world.o).index];
    let pmf = light.d.w;
    if (light.kind != LIGHT_POINT || pmf <= 0.0) {
        return vec3<f32>(0.0);
    }
    let sh = shading[0];
    let s = Segment(world, index, range.x, range.y, light.a.xyz, light.b.xyz, sh.w, sh.xyz);
    return point_mis_radiance(m, s, &rng, lookups) / pmf;
}


// Integrators `direct` and `volpath` (direct = volpath with max_depth 1),
// mirroring integrators/volpath.rs, next_event.rs and free_flight.rs sample
// for sample: free-flight sampling across media up to the next surface,
// next-event estimation toward one light chosen by power with the
// transmittance estimator ESTIMATOR, environments and emitting shapes
// MIS-combined with phase or BSDF sampling (at the last vertex the sampled
// direction is evaluated toward the lights instead of traced), Russian
// roulette on the throughput after rr_depth bounces. With
// INTEGRATOR_LIGHT_ONLY (volpath's restir_baseline preset, Lin et al. 2021 §6):
// light sampling only, no sampled escape, roulette by albedo.
//
// Medium and surface vertices share one body (`scatter`) with a single
// call of shadow(): lavapipe's compiler inlines every call site, and with
// the surface walk four sites made the kernel take minutes to compile.

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
// view ray; `from_camera` while it still starts at the camera) before
// t_end, in bounded medium `current` (+ 1): (t, medium index) or t < 0.
fn next_collision(world: Ray, depth: u32, from_camera: bool, t_end: f32, current: u32,
                  rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> vec2<f32> {
    let kind = flight_kind(depth);
    var hit = vec2<f32>(NO_HIT, 0.0);
    for (var i = 0u; i < frame.media_count; i++) {
        if (!medium_active(i, current)) {
            continue;
        }
        let m = media[i];
        var t_max = t_end;
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

// free_flight::media_transmittance for NEE at scattering vertex `vertex`,
// per channel: a chromatic medium of constant channel ratios shares one
// walk between its channels where the estimator can
// (tracking::transmittance_rgb, estimate_rgb); otherwise each channel is
// estimated with its own medium (Chroma::transmittance; channels of equal
// constant k share one estimate). One estimator call site, for lavapipe's
// compile time.
fn media_shadow(world: Ray, distance: f32, vertex: u32, current: u32,
                rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> vec3<f32> {
    let kind = shadow_kind(vertex);
    var tr = vec3<f32>(1.0);
    for (var i = 0u; i < frame.media_count; i++) {
        if (!medium_active(i, current)) {
            continue;
        }
        let first = chroma_first(i);
        let k_varies = first != 0u && chroma_varying(i);
        var k = vec3<f32>(1.0);
        if (first != 0u && !k_varies) {
            k = chroma_k(i, first);
        }
        if ((INTEGRATOR_FLAGS & INTEGRATOR_CHROMATIC) != 0u && first != 0u && !k_varies
            && kind == TRACK_UNBIASED) {
            let m = media[i];
            var r: Ray;
            let range = to_index(m, world, distance, &r);
            if (range.z == 0.0) {
                continue;
            }
            let shared_walk = estimate_rgb(m, r, range.x, range.y, k, rng, lookups);
            if (shared_walk.w != 0.0) {
                tr *= shared_walk.xyz;
                continue;
            }
        }
        var t = vec3<f32>(1.0);
        for (var c = 0u; c < select(1u, 3u, first != 0u); c++) {
            var same = c;
            for (var b = 0u; b < c; b++) {
                if (same == c && !k_varies && k[b] == k[c]) {
                    same = b;
                }
            }
            if (same != c) {
                t[c] = t[same];
                continue;
            }
            let mi = select(i, first - 1u + c, first != 0u);
            let m = media[mi];
            var r: Ray;
            let range = to_index(m, world, distance, &r);
            if (range.z != 0.0) {
                t[c] = tracked_transmittance(kind, mi, m, r, range.x, range.y, rng, lookups);
            }
        }
        tr *= select(t, vec3<f32>(t.x), first == 0u);
    }
    return tr;
}

fn has_environment() -> bool {
    return env.environments > 0u;
}

// A path between vertices (volpath.rs `Path`).
struct Path {
    ray: Ray,
    beta: vec3<f32>,
    radiance: vec3<f32>,
    // The last scattering vertex, the solid-angle pdf its direction was
    // sampled with and whether it is on a surface, for MIS with light
    // sampling (pdf < 0: camera ray or delta lobe). Null boundaries leave
    // them unchanged.
    prev_p: vec3<f32>,
    prev_pdf: f32,
    prev_surface: bool,
    // The bounded medium the path is in, + 1 (0: none).
    medium: u32,
}

// What a vertex did to the path (volpath.rs `Step`).
const STEP_STOP: u32 = 0u;
const STEP_SCATTER: u32 = 1u;
// Straight through an index-matched boundary: not a vertex.
const STEP_CROSS: u32 = 2u;
// A null collision of a chromatic medium: not a vertex either.
const STEP_NULL: u32 = 3u;

// Null collisions of chromatic media one path may take (volpath.rs).
const MAX_NULL_COLLISIONS: u32 = 16777216u;

// Index-matched boundaries a ray may cross in a row (free_flight.rs).
const MAX_CROSSINGS: u32 = 1024u;

// A scattering vertex: a real collision in a medium (HG phase g) or a
// surface hit with the BSDF of the side wo sees (twosided resolved once:
// the back side works in the mirrored local frame, as TwoSided does).
struct Vertex {
    p: vec3<f32>,
    // The direction the path arrived along.
    d: vec3<f32>,
    surface: bool,
    g: f32,
    albedo: vec3<f32>,
    hit: Hit,
    bsdf: Bsdf,
    back: bool,
    // Light sampling can help (not every lobe of both sides a delta).
    nee: bool,
    sf: ShadingFrame,
    wo: vec3<f32>,
}

// A world direction in the vertex's BSDF frame (mirrored on the back side).
fn vertex_local(v: Vertex, w: vec3<f32>) -> vec3<f32> {
    let l = to_local(v.sf, w);
    return select(l, flip_z(l), v.back);
}

fn vertex_world(v: Vertex, l: vec3<f32>) -> vec3<f32> {
    return to_world(v.sf, select(l, flip_z(l), v.back));
}

// A shadow segment and what its transmittance multiplies.
struct ShadowQuery {
    valid: bool,
    ray: Ray,
    distance: f32,
    medium: u32,
    le: vec3<f32>,
    // Medium NEE: le · (fs · T · w / den); surface NEE: le · fv · (T · w /
    // den); a sampled direction (den = 0): le · (w · T), or le · T for the
    // environment (w < 0). Each the CPU's expression, in its order.
    fs: f32,
    fv: vec3<f32>,
    w: f32,
    den: f32,
}

fn no_query() -> ShadowQuery {
    var q: ShadowQuery;
    q.valid = false;
    return q;
}

fn query_value(q: ShadowQuery, surface: bool, tr: vec3<f32>) -> vec3<f32> {
    if (q.den == 0.0) {
        if (q.w < 0.0) {
            return q.le * tr;
        }
        return q.le * (q.w * tr);
    }
    if (surface) {
        return q.le * q.fv * (tr * q.w / q.den);
    }
    return q.le * (q.fs * tr * q.w / q.den);
}

// next_event::light_sample (medium) and light_sample_surface:
// one light picked (LightSampler, by vertex kind), sampled, weighted against phase or BSDF
// sampling by the balance heuristic (not for delta lights, nor with
// INTEGRATOR_LIGHT_ONLY); the shadow ray leaves a surface from the
// light's side, in the medium there.
fn light_query(v: Vertex, current: u32, rng: ptr<function, Pcg32>) -> ShadowQuery {
    // The CPU draws the selection number before finding there is no light.
    let u_pick = pcg32_next_f32(rng);
    if (env.pickable == 0u) {
        return no_query();
    }
    let picked = pick_light(u_pick, v.surface, v.p);
    if (picked.index == NO_LIGHT) {
        return no_query();
    }
    let light = lights[picked.index];
    let pmf = picked.pmf;
    let u0 = pcg32_next_f32(rng);
    let u1 = pcg32_next_f32(rng);
    let ls = light_sample_li(light, v.p, u0, u1);
    if (!ls.valid) {
        return no_query();
    }
    var q: ShadowQuery;
    q.valid = true;
    q.le = ls.radiance;
    q.distance = ls.distance;
    var pdf_dir: f32;
    if (v.surface) {
        let wi = vertex_local(v, ls.wi);
        q.fv = bsdf_eval(v.bsdf, v.wo, wi) * abs(wi.z);
        if (all(q.fv == vec3<f32>(0.0)) || all(ls.radiance == vec3<f32>(0.0))) {
            return no_query();
        }
        q.fs = 1.0;
        q.medium = target_medium(v.hit, ls.wi, current);
        q.ray = Ray(spawn_origin(v.hit, ls.wi), ls.wi);
        pdf_dir = bsdf_pdf(v.bsdf, v.wo, wi);
    } else {
        q.fs = hg_eval(v.g, dot(v.d, ls.wi));
        if (q.fs <= 0.0 || all(ls.radiance == vec3<f32>(0.0))) {
            return no_query();
        }
        q.fv = vec3<f32>(1.0);
        q.medium = current;
        q.ray = Ray(v.p, ls.wi);
        pdf_dir = q.fs;
    }
    q.w = 1.0;
    if (ls.is_delta) {
        q.den = pmf;
    } else if (light_only()) {
        q.den = pmf * ls.pdf;
    } else {
        q.den = pmf * ls.pdf;
        q.w = balance(q.den, pdf_dir);
    }
    return q;
}

// VolPath::roulette: on the throughput from rr_depth on (the baseline: on
// the vertex albedo).
fn roulette(path: ptr<function, Path>, depth: u32, albedo: vec3<f32>,
            rng: ptr<function, Pcg32>) -> u32 {
    if (depth + 1u >= frame.rr_depth) {
        let beta = (*path).beta;
        var q = min(max(beta.x, max(beta.y, beta.z)), 1.0);
        if (light_only()) {
            q = min(max(albedo.x, max(albedo.y, albedo.z)), 1.0);
        }
        if (pcg32_next_f32(rng) >= q) {
            return STEP_STOP;
        }
        (*path).beta /= q;
    }
    return STEP_SCATTER;
}

// The vertex a medium collision at (t, medium) `c` makes, after its
// emission and albedo (VolPath::medium_vertex's start); invalid (g = 2)
// when the throughput is gone, a null collision (g = 3) when the path
// passes a chromatic medium's collision.
fn medium_start(path: ptr<function, Path>, c: vec2<f32>,
                rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> Vertex {
    let ray = (*path).ray;
    let mi = u32(c.y);
    var v: Vertex;
    v.surface = false;
    v.d = ray.d;
    v.g = shading[mi].w;
    v.p = ray.o + c.x * ray.d;
    v.albedo = albedo_at(mi, v.p);
    let first = chroma_first(mi);
    if (first != 0u) {
        // Chroma::event: a collision of the tracked (largest) channel; each
        // channel scatters, absorbs (emits) or passes with its own
        // probability, the path picks scatter or pass by the larger weight.
        let k = chroma_k_at(mi, first, v.p, lookups);
        (*path).radiance += (*path).beta * (emitted(mi, v.p, v.albedo) * k);
        let beta = (*path).beta;
        let scatter = v.albedo * k;
        let passed = vec3<f32>(1.0) - k;
        let bs = beta * scatter;
        let bp = beta * passed;
        let ws = max(bs.x, max(bs.y, bs.z));
        let wp = max(bp.x, max(bp.y, bp.z));
        let u = pcg32_next_f32(rng);
        if (!(ws + wp > 0.0)) {
            v.g = 2.0;
            return v;
        }
        let p_scatter = ws / (ws + wp);
        if (u >= p_scatter) {
            (*path).beta *= passed / (1.0 - p_scatter);
            (*path).ray = Ray(v.p, ray.d);
            v.g = 3.0;
            return v;
        }
        v.albedo = scatter / p_scatter;
    } else {
        (*path).radiance += (*path).beta * emitted(mi, v.p, v.albedo);
    }
    (*path).beta *= v.albedo;
    if (all((*path).beta == vec3<f32>(0.0))) {
        v.g = 2.0;
    }
    return v;
}

// VolPath::surface_vertex's start: the hit's emission (MIS-weighted
// against light sampling), its BSDF; null boundaries are crossed here
// (returns false).
fn surface_start(path: ptr<function, Path>, h: Hit, v: ptr<function, Vertex>) -> bool {
    let d = (*path).ray.d;
    let e = surface_emitted(h, d);
    if (e.valid && !(light_only() && (*path).prev_pdf >= 0.0)) {
        let w = emitter_weight(e.light, h.p, d, (*path).prev_p, (*path).prev_pdf,
                               (*path).prev_surface);
        (*path).radiance += (*path).beta * e.le * w;
    }
    if (shape_is_null(h.shape)) {
        (*path).medium = target_medium(h, d, (*path).medium);
        (*path).ray = Ray(spawn_origin(h, d), d);
        return false;
    }
    (*v).surface = true;
    (*v).p = h.p;
    (*v).d = d;
    (*v).hit = h;
    (*v).sf = shading_frame(h.ns);
    let wo = to_local((*v).sf, -d);
    (*v).back = is_two_sided(h.shape) && wo.z < 0.0;
    (*v).bsdf = surface_bsdf(h, (*v).back);
    (*v).nee = !material_is_delta(h.shape);
    (*v).wo = select(wo, flip_z(wo), (*v).back);
    return true;
}

// The rest of a vertex: NEE, then phase or BSDF sampling, and at the last
// vertex the sampled direction evaluated toward the lights — both shadow
// segments through the one shadow() call of the kernel.
fn scatter(path: ptr<function, Path>, v: Vertex, depth: u32,
           rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> u32 {
    let current = (*path).medium;
    var weight = vec3<f32>(1.0);
    for (var k = 0u; k < 2u; k++) {
        var q = no_query();
        if (k == 0u) {
            if (!v.surface || v.nee) {
                q = light_query(v, current, rng);
            }
        } else {
            // Phase sampling is exact (pdf = f); BSDF sampling picks a lobe.
            var wi: vec3<f32>;
            var pdf: f32;
            var origin = v.p;
            var next = current;
            if (v.surface) {
                let uc = pcg32_next_f32(rng);
                let u0 = pcg32_next_f32(rng);
                let u1 = pcg32_next_f32(rng);
                let bs = bsdf_sample(v.bsdf, v.wo, uc, u0, u1);
                if (!bs.valid) {
                    return STEP_STOP;
                }
                weight = bs.f * abs(bs.wi.z) / bs.pdf;
                let top = max(weight.x, max(weight.y, weight.z));
                if (!(finite(weight.x) && finite(weight.y) && finite(weight.z) && top > 0.0)) {
                    return STEP_STOP;
                }
                wi = vertex_world(v, bs.wi);
                pdf = select(bs.pdf, -1.0, bs.delta);
                next = target_medium(v.hit, wi, current);
                if (bs.delta && all(bs.wi == -v.wo) && (shape_flags(v.hit.shape) & SHAPE_PASSES) != 0u) {
                    // Straight through a thin dielectric: a crossing, as in Mitsuba.
                    (*path).beta *= weight;
                    (*path).medium = next;
                    (*path).ray = Ray(spawn_origin(v.hit, v.d), v.d);
                    return STEP_CROSS;
                }
                origin = spawn_origin(v.hit, wi);
            } else {
                let u0 = pcg32_next_f32(rng);
                let u1 = pcg32_next_f32(rng);
                let s = hg_sample(v.g, -v.d, u0, u1);
                wi = s.xyz;
                pdf = s.w;
            }
            if (depth + 1u != frame.max_depth) {
                (*path).beta *= weight;
                (*path).prev_p = v.p;
                (*path).prev_pdf = pdf;
                (*path).prev_surface = v.surface;
                (*path).medium = next;
                (*path).ray = Ray(origin, wi);
                var albedo = weight;
                if (!v.surface) {
                    albedo = v.albedo;
                }
                return roulette(path, depth, albedo, rng);
            }
            if (light_only()) {
                return STEP_STOP;
            }
            q = direction_query(v.p, Ray(origin, wi), pdf, v.surface, next);
        }
        if (q.valid) {
            let tr = shadow(q.ray, q.distance, depth, q.medium, rng, lookups);
            (*path).radiance += (*path).beta * weight * query_value(q, v.surface && k == 0u, tr);
        }
    }
    return STEP_STOP;
}

// World::in_medium: whether p, reached by a ray in bounded medium
// `current` (+ 1), lies in a medium (the bounded one, or the box of one
// that exists there).
fn in_medium(current: u32, p: vec3<f32>) -> bool {
    if (current != 0u) {
        return true;
    }
    for (var i = 0u; i < frame.media_count; i++) {
        let m = media[i];
        let q = vec3<f32>(dot(m.w2i0.xyz, p) + m.w2i0.w, dot(m.w2i1.xyz, p) + m.w2i1.w,
                          dot(m.w2i2.xyz, p) + m.w2i2.w);
        if (medium_active(i, current) && all(q >= vec3<f32>(0.0)) && all(q <= vec3<f32>(m.dims))) {
            return true;
        }
    }
    return false;
}

fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
    var path: Path;
    path.ray = primary_ray(x, y, pixel, sample);
    path.beta = vec3<f32>(1.0);
    path.radiance = vec3<f32>(0.0);
    path.prev_p = vec3<f32>(0.0);
    path.prev_pdf = -1.0;
    path.prev_surface = false;
    path.medium = camera_medium();
    if ((INTEGRATOR_FLAGS & INTEGRATOR_TRANSMITTANCE) != 0u) {
        // transmittance.rs `sample` with surfaces or chromatic media: the
        // background seen through them along the camera ray.
        return frame.background.xyz * shadow(path.ray, camera_ray_end(path.ray), 0u, path.medium, &rng, lookups);
    }
    var depth = 0u;
    var crossings = 0u;
    var nulls = 0u;
    // The camera ray's first segment ends on the far clip plane.
    let camera_end = camera_ray_end(path.ray);
    while (depth < frame.max_depth) {
        let from_camera = depth == 0u && crossings == 0u && nulls == 0u;
        let t_limit = select(F32_INF, camera_end, from_camera);
        let hit = intersect_surfaces(path.ray.o, path.ray.d, t_limit, false);
        let t_end = select(t_limit, hit.t, hit.valid);
        let c = next_collision(path.ray, depth, from_camera, t_end, path.medium, &rng, lookups);
        var step = STEP_CROSS;
        if (c.x >= 0.0) {
            let v = medium_start(&path, c, &rng, lookups);
            step = STEP_STOP;
            if (v.g == 3.0) {
                step = STEP_NULL;
            } else if (v.g != 2.0) {
                step = scatter(&path, v, depth, &rng, lookups);
            }
        } else if (hit.valid) {
            var v: Vertex;
            if (surface_start(&path, hit, &v)) {
                step = scatter(&path, v, depth, &rng, lookups);
            }
        } else {
            // World::lost_at_far_clip: ended on the far plane inside a medium.
            let lost = from_camera && t_limit < F32_INF
                && in_medium(path.medium, path.ray.o + t_limit * path.ray.d);
            if (!lost && !(light_only() && path.prev_pdf >= 0.0)) {
                path.radiance += path.beta * escaped(path.ray.d, path.prev_pdf, path.prev_surface);
            }
            step = STEP_STOP;
        }
        if (step == STEP_STOP) {
            break;
        }
        if (step == STEP_SCATTER) {
            depth++;
        } else if (step == STEP_NULL) {
            nulls++;
            if (nulls > MAX_NULL_COLLISIONS) {
                break;
            }
        } else {
            crossings++;
            if (crossings > MAX_CROSSINGS) {
                break;
            }
        }
    }
    return path.radiance;
}

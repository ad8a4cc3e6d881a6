// fogbank_render::integrators::restir::target on the GPU: the path integrand
// F and the target p̂ (Lin et al. 2021 Eq. 12–15, 22–23), one evaluation of a
// stored path along a pixel's primary ray. MODE_TARGET attenuates segments
// with T̃ (p̂, deterministic); MODE_F with the shading estimator (F).

// target::environment: radiance of every environment light along d.
fn restir_environment(d: vec3<f32>) -> vec3<f32> {
    var l = vec3<f32>(0.0);
    for (var i = 0u; i < env.light_count; i++) {
        if (is_environment(lights[i])) {
            l += light_le(lights[i], d);
        }
    }
    return l;
}

// target::evaluate: the path's contribution along ray0 (unit direction).
// Step i < k is the path's segment i; step k its last segment, to its
// light — or, for a path that leaves to the background, the primary ray
// itself (then k = 0). Every step is attenuated at the one call of
// segment_t: drivers inline every call, and this function is inlined at
// each p̂ evaluation of a pass (lavapipe's compile time grows with each copy).
fn evaluate(ray0: Ray, y: ptr<function, Path>, mode: u32, rng: ptr<function, Pcg32>,
            lookups: ptr<function, u32>) -> vec3<f32> {
    let background = (*y).end == END_BACKGROUND;
    var k = min((*y).k, MAX_K);
    if (background) {
        k = 0u;
    }
    let g = shading[0].w;
    var x = ray0.o;
    var d = ray0.d;
    var f = vec3<f32>(1.0);
    // The current vertex when it lies on a surface (restir/surface.wgsl).
    var at_surface = false;
    var hit = no_hit();
    for (var i = 0u; i <= k; i++) {
        // The step's segment, its length, and the factors before and after
        // its transmittance.
        var seg: Ray;
        var dist: f32;
        var before: vec3<f32>;
        var after = vec3<f32>(1.0);
        // A segment ending on the closest surface needs no visibility test.
        var to_surface = false;
        if (i < k) {
            let last = i + 1u == k;
            // Segment i: from x_i along ω_i to x_{i+1}. On the path's own
            // vertices the stored ω, z rebuild x_{i+1} exactly (as the CPU).
            let fixed = is_fixed(y, i);
            var own = false;
            if (i >= 1u) {
                own = all(x == (*y).x[i - 1u]);
            }
            var next_d: vec3<f32>;
            var z: f32;
            var geom = 1.0;
            if (fixed && own) {
                next_d = (*y).dir[i - 1u];
                z = (*y).z[i];
                geom = 1.0 / (z * z);
            } else if (fixed) {
                let v = (*y).x[i] - x;
                z = length(v);
                if (!(z > 0.0)) {
                    return vec3<f32>(0.0);
                }
                next_d = v / z;
                geom = 1.0 / (z * z);
            } else {
                if (i == 0u) {
                    next_d = d;
                } else {
                    next_d = (*y).dir[i - 1u];
                }
                z = (*y).z[i];
            }
            if (i > 0u) {
                f *= vertex_scatter(at_surface, hit, g, d, next_d);
            }
            d = next_d;
            seg = vertex_leave(at_surface, hit, x, d);
            if (on_surface(y, i)) {
                // The closest surface along the segment (§4.2).
                let h = intersect_surfaces(seg.o, seg.d, F32_INF, true);
                if (!h.valid) {
                    return vec3<f32>(0.0);
                }
                to_surface = true;
                dist = h.t;
                x = h.p;
                hit = h;
                at_surface = true;
                before = vec3<f32>(1.0);
                if (last && (*y).end == END_EMISSION) {
                    let e = surface_emitted(h, d);
                    after = select(vec3<f32>(0.0), e.le, e.valid);
                }
            } else {
                x = ray_at(seg, z);
                at_surface = false;
                let sigma = restir_sigma_t(x);
                if (sigma <= 0.0) {
                    return vec3<f32>(0.0);
                }
                let albedo = albedo_at(0u, x);
                dist = z;
                before = vec3<f32>(geom);
                if (last && (*y).end == END_EMISSION) {
                    after = emitted(0u, x, albedo) * sigma;
                } else {
                    after = albedo * sigma;
                }
            }
        } else if (background) {
            let le = restir_environment(ray0.d);
            if (all(le == vec3<f32>(0.0))) {
                return vec3<f32>(0.0);
            }
            seg = ray0;
            dist = F32_INF;
            before = le;
        } else if ((*y).end == END_LIGHT) {
            if ((*y).light >= env.light_count) {
                return vec3<f32>(0.0);
            }
            // target::light_towards: environments keep the stored direction,
            // emitting shapes the stored point (area measure), other lights
            // are seen from x (their sampling ignores u).
            let l = lights[(*y).light];
            var wi = (*y).light_dir;
            var li: vec3<f32>;
            dist = F32_INF;
            if (is_environment(l)) {
                li = light_le(l, wi);
            } else {
                var ls: LightSample;
                if (is_shape_light(l)) {
                    ls = shape_toward_point(l, x, (*y).light_point);
                } else {
                    ls = light_sample_li(l, x, 0.5, 0.5);
                }
                if (!ls.valid) {
                    return vec3<f32>(0.0);
                }
                wi = ls.wi;
                li = ls.radiance;
                dist = ls.distance;
            }
            let fs = vertex_scatter(at_surface, hit, g, d, wi);
            if (all(fs == vec3<f32>(0.0)) || all(li == vec3<f32>(0.0))) {
                return vec3<f32>(0.0);
            }
            seg = vertex_leave(at_surface, hit, x, wi);
            before = li * fs;
        } else {
            break;
        }
        // Every step a surface cuts is worth nothing, in p̂ and F alike.
        if (!to_surface && !visible(seg, dist)) {
            return vec3<f32>(0.0);
        }
        f *= before * segment_t(mode, seg, dist, rng, lookups);
        f *= after;
        if (all(f == vec3<f32>(0.0))) {
            return vec3<f32>(0.0);
        }
    }
    return f;
}

// Restir::p_hat: the reuse target, luminance of the path with T̃.
fn p_hat_of(ray0: Ray, y: ptr<function, Path>, lookups: ptr<function, u32>) -> f32 {
    var unused = Pcg32(vec2<u32>(0u), vec2<u32>(1u, 0u));
    return max(luminance(evaluate(ray0, y, MODE_TARGET, &unused, lookups)), 0.0);
}

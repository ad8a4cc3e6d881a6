// fogbank_render::integrators::restir::target on the GPU: the path integrand
// F and the target p̂ (seed 002 Eq. 12–15, 22–23), one evaluation of a
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
fn evaluate(ray0: Ray, y: ptr<function, Path>, mode: u32, rng: ptr<function, Pcg32>,
            lookups: ptr<function, u32>) -> vec3<f32> {
    if ((*y).end == END_BACKGROUND) {
        let le = restir_environment(ray0.d);
        if (all(le == vec3<f32>(0.0))) {
            return vec3<f32>(0.0);
        }
        return le * segment_t(mode, ray0, F32_INF, rng, lookups);
    }
    let g = shading[0].w;
    let k = min((*y).k, MAX_K);
    var x = ray0.o;
    var d = ray0.d;
    var f = vec3<f32>(1.0);
    for (var i = 0u; i < k; i++) {
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
            f *= hg_pdf(g, -d, next_d);
        }
        d = next_d;
        var seg: Ray;
        seg.o = x;
        seg.d = d;
        x = ray_at(seg, z);
        let sigma = restir_sigma_t(x);
        if (sigma <= 0.0) {
            return vec3<f32>(0.0);
        }
        let albedo = albedo_at(0u, x);
        f *= geom * segment_t(mode, seg, z, rng, lookups);
        if (last && (*y).end == END_EMISSION) {
            f *= emitted(0u, x, albedo) * sigma;
        } else {
            f *= albedo * sigma;
        }
        if (all(f == vec3<f32>(0.0))) {
            return vec3<f32>(0.0);
        }
    }
    if ((*y).end == END_LIGHT) {
        if ((*y).light >= env.light_count) {
            return vec3<f32>(0.0);
        }
        // target::light_towards: environments keep the stored direction,
        // other lights are seen from x (their sampling ignores u).
        let l = lights[(*y).light];
        var wi = (*y).light_dir;
        var li: vec3<f32>;
        var dist = F32_INF;
        if (is_environment(l)) {
            li = light_le(l, wi);
        } else {
            let ls = light_sample_li(l, x, 0.5, 0.5);
            if (!ls.valid) {
                return vec3<f32>(0.0);
            }
            wi = ls.wi;
            li = ls.radiance;
            dist = ls.distance;
        }
        let fp = hg_pdf(g, -d, wi);
        if (fp <= 0.0 || all(li == vec3<f32>(0.0))) {
            return vec3<f32>(0.0);
        }
        var sr: Ray;
        sr.o = x;
        sr.d = wi;
        f *= li * fp * segment_t(mode, sr, dist, rng, lookups);
    }
    return f;
}

// Restir::p_hat: the reuse target, luminance of the path with T̃.
fn p_hat_of(ray0: Ray, y: ptr<function, Path>, lookups: ptr<function, u32>) -> f32 {
    var unused = Pcg32(vec2<u32>(0u), vec2<u32>(1u, 0u));
    return max(luminance(evaluate(ray0, y, MODE_TARGET, &unused, lookups)), 0.0);
}

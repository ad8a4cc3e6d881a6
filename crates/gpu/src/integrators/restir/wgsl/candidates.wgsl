// fogbank_render::integrators::restir::candidates on the GPU (Lin et al. 2021
// §3.2–3.3, §4.1, Fig. 3): M random walks per pixel through the
// conservative mips, each streaming its scattering (NEE), emission and
// background candidates into the pixel's reservoir with w = p̂/p; a walk
// counts M = 1 (Eq. 19–21); Russian roulette by albedo after x_rr_depth
// when K > rr_depth (§6.1). The chosen path is then moved to the reuse
// target (§4.3).

fn emissive() -> bool {
    return u32(medium_ext(0u).z) != EMISSION_NONE;
}

// Restir::nee_candidate: next-event estimation from vertex x (reached along
// d; on surface h when `surface`) toward one light picked by power, with the
// vertex's scattering factor and T̃ of the NEE mip on the shadow segment
// (Fig. 11). An emitting shape's point is kept with the path, in its area
// measure (p̂ and p both carry |cos θ_q|/|q − x|², so w is unchanged).
fn nee_candidate(y: ptr<function, Path>, x: vec3<f32>, d: vec3<f32>, surface: bool, h: Hit,
                 beta: vec3<f32>, p_walk: f32, g: f32, rng: ptr<function, Pcg32>,
                 res: ptr<function, Reservoir>, lookups: ptr<function, u32>) {
    let u_pick = pcg32_next_f32(rng);
    let u0 = pcg32_next_f32(rng);
    let u1 = pcg32_next_f32(rng);
    let u_keep = pcg32_next_f32(rng);
    if (env.pickable == 0u) {
        return;
    }
    let picked = pick_light(u_pick, surface, x);
    if (picked.index == NO_LIGHT) {
        return;
    }
    let li = picked.index;
    let pmf = picked.pmf;
    let l = lights[li];
    let ls = light_sample_li(l, x, u0, u1);
    if (!ls.valid) {
        return;
    }
    let fs = vertex_scatter(surface, h, g, d, ls.wi);
    let sr = vertex_leave(surface, h, x, ls.wi);
    if (all(fs == vec3<f32>(0.0)) || all(ls.radiance == vec3<f32>(0.0)) || !visible(sr, ls.distance)) {
        return;
    }
    var t_nee = 1.0;
    if (rp.nee_transmittance != 0u) {
        t_nee = marched_t(rp.nee_record, 1.0, sr, ls.distance, lookups);
    }
    var p_light = pmf;
    if (!ls.is_delta) {
        p_light *= ls.pdf;
    }
    let w = luminance(beta * ls.radiance * (fs * t_nee)) / p_light;
    var yl = *y;
    yl.end = END_LIGHT;
    yl.light = li;
    yl.light_dir = ls.wi;
    var p_y = p_walk * p_light;
    if (is_shape_light(l)) {
        // The point light_sample_li drew (the same numbers draw it again).
        let q = shape_light_point(l, x, u0, u1).xyz;
        yl.light_point = q;
        p_y *= shape_area_factor(l, x, q);
    }
    res_stream(res, &yl, w, w * p_y, u_keep);
}

// Restir::walk: one random walk, streaming its candidates into res. A walk
// that reaches a surface before its next collision (probability T* up to
// it) makes it a vertex (Restir::surface_vertex).
fn walk(ray0: Ray, rng: ptr<function, Pcg32>, res: ptr<function, Reservoir>,
        lookups: ptr<function, u32>) {
    let g = shading[0].w;
    var y = background_path();
    if (rp.vertex_reuse != 0u) {
        y.fixed_from = 1u;
    }
    // ∏ 1/z² over fixed vertices (vertex reuse), as evaluate computes it.
    var g_fixed = 1.0;
    var ray = ray0;
    var beta = vec3<f32>(1.0);
    var p_walk = 1.0;
    for (var k = 1u; k <= rp.max_depth; k++) {
        var record = rp.indirect_record;
        if (k == 1u) {
            record = rp.primary_record;
        }
        let h = intersect_surfaces(ray.o, ray.d, F32_INF, true);
        let t_surface = select(F32_INF, h.t, h.valid);
        let flight = restir_track(record, ray, t_surface, rng, lookups);
        if (flight.t < 0.0 || flight.t >= t_surface) {
            let p_pass = exp(-flight.tau);
            if (!h.valid) {
                if (k == 1u) {
                    // p = T* of the whole ray, p̂ = T*·lum(L_env): w = lum(L_env).
                    let w = luminance(restir_environment(ray.d));
                    var bg = background_path();
                    res_stream(res, &bg, w, w * p_pass, pcg32_next_f32(rng));
                }
                return;
            }
            // Restir::surface_vertex.
            p_walk *= p_pass;
            y.k = k;
            y.surface |= 1u << (k - 1u);
            y.z[k - 1u] = h.t;
            y.x[k - 1u] = h.p;
            if (k == 1u) {
                // An emitter seen from the camera: w = lum(L_e).
                let e = surface_emitted(h, ray.d);
                let we = select(0.0, luminance(e.le), e.valid);
                if (we > 0.0) {
                    var ye = y;
                    ye.end = END_EMISSION;
                    res_stream(res, &ye, we, we * p_walk, pcg32_next_f32(rng));
                }
            }
            nee_candidate(&y, h.p, ray.d, true, h, beta, p_walk, g, rng, res, lookups);
            if (k == rp.max_depth) {
                return;
            }
            let s = surface_side(h, ray.d);
            let uc = pcg32_next_f32(rng);
            let u0 = pcg32_next_f32(rng);
            let u1 = pcg32_next_f32(rng);
            let bs = bsdf_sample(s.bsdf, s.wo, uc, u0, u1);
            if (!bs.valid || bs.delta) {
                return;
            }
            let weight = bs.f * abs(bs.wi.z) / bs.pdf;
            let top = max(weight.x, max(weight.y, weight.z));
            if (!(bs.pdf > 0.0 && finite(weight.x) && finite(weight.y) && finite(weight.z) && top > 0.0)) {
                return;
            }
            let wi = to_world(s.sf, select(bs.wi, flip_z(bs.wi), s.back));
            p_walk *= bs.pdf;
            beta *= weight;
            y.dir[k - 1u] = wi;
            if (k >= rp.rr_depth) {
                let q = clamp(top, 0.0, 1.0);
                if (pcg32_next_f32(rng) >= q) {
                    return;
                }
                p_walk *= q;
                beta /= q;
            }
            ray.o = spawn_origin(h, wi);
            ray.d = wi;
            continue;
        }
        let t = flight.t;
        let x = ray_at(ray, t);
        p_walk *= exp(-flight.tau) * flight.sigma_t;
        let sigma = restir_sigma_t(x);
        if (sigma <= 0.0 || flight.sigma_t <= 0.0) {
            return;
        }
        let albedo = albedo_at(0u, x);
        y.k = k;
        y.z[k - 1u] = t;
        y.x[k - 1u] = x;
        if (is_fixed(&y, k - 1u)) {
            g_fixed *= 1.0 / (t * t);
        }
        let inv_sigma_star = 1.0 / flight.sigma_t;
        if (emissive()) {
            var ye = y;
            ye.end = END_EMISSION;
            var p_e = p_walk * g_fixed;
            if (k >= 2u && !is_fixed(&ye, k - 1u)) {
                // An emitter is kept fixed in space under reuse.
                ye.fixed_from = k - 1u;
                p_e *= 1.0 / (t * t);
            }
            let w = luminance(beta * emitted(0u, x, albedo) * (sigma * inv_sigma_star));
            res_stream(res, &ye, w, w * p_e, pcg32_next_f32(rng));
        }
        nee_candidate(&y, x, ray.d, false, no_hit(), beta * albedo * (sigma * inv_sigma_star),
                      p_walk * g_fixed, g, rng, res, lookups);
        beta *= albedo * (sigma * inv_sigma_star);
        if (k == rp.max_depth) {
            return;
        }
        let u0 = pcg32_next_f32(rng);
        let u1 = pcg32_next_f32(rng);
        let s = hg_sample(g, -ray.d, u0, u1);
        p_walk *= s.w;
        y.dir[k - 1u] = s.xyz;
        if (k >= rp.rr_depth) {
            let q = clamp(max(albedo.x, max(albedo.y, albedo.z)), 0.0, 1.0);
            if (pcg32_next_f32(rng) >= q) {
                return;
            }
            p_walk *= q;
            beta /= q;
        }
        ray.o = x;
        ray.d = s.xyz;
    }
}

// velocity_resampling::pick (§5.2): a medium point on the world ray drawn
// ∝ σ_t·T through mip 1, voxel by weighted reservoir sampling then uniform
// within it; t < 0 when the ray sees no medium.
fn resample_point(world: Ray, rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    let m = media[rp.mip1_record];
    var r: Ray;
    let range = to_index(m, world, F32_INF, &r);
    if (range.z == 0.0) {
        return NO_HIT;
    }
    var tau = 0.0;
    var w_sum = 0.0;
    var chosen = vec2<f32>(NO_HIT, NO_HIT);
    var dda = dda_new(r, 1.0, m.dims, range.x, range.y);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        *lookups += 1u;
        let sigma_t = m.scale * fetch(m, s.cell.x, s.cell.y, s.cell.z);
        let len = s.t1 - s.t0;
        if (sigma_t > 0.0 && len > 0.0) {
            // The mean of σ_t·T over the voxel: T(entry)(1 − e^{−σ_t·Δ})/Δ.
            let w = exp(-tau) * (1.0 - exp(-sigma_t * len)) / len;
            w_sum += w;
            if (pcg32_next_f32(rng) * w_sum < w) {
                chosen = vec2<f32>(s.t0, s.t1);
            }
        }
        tau += sigma_t * len;
        if (tau > 30.0) {
            break;
        }
    }
    if (chosen.x < 0.0) {
        return NO_HIT;
    }
    return chosen.x + pcg32_next_f32(rng) * (chosen.y - chosen.x);
}

// Velocity::at of the current frame's medium (world lengths per second):
// a grid of three property records turned to world vectors, or an affine
// field inside its box (VelocityGpu in src/restir/uniform.rs).
fn velocity_at(p: vec3<f32>) -> vec3<f32> {
    let o = vec4<f32>(p, 1.0);
    let v = rp.velocity;
    if (rp.velocity_kind == VELOCITY_GRID) {
        let f = field_eval(rp.velocity_record, 3u, p);
        return vec3<f32>(dot(v[0].xyz, f), dot(v[1].xyz, f), dot(v[2].xyz, f));
    }
    if (rp.velocity_kind == VELOCITY_AFFINE) {
        let u = vec3<f32>(dot(v[3], o), dot(v[4], o), dot(v[5], o));
        if (any(u < vec3<f32>(0.0)) || any(u > vec3<f32>(1.0))) {
            return vec3<f32>(0.0);
        }
        return vec3<f32>(dot(v[0], o), dot(v[1], o), dot(v[2], o));
    }
    return vec3<f32>(0.0);
}

// The first part of Restir::temporal, run with the current frame's data:
// the two pixel-pick numbers, then what the pixel saw (x_1 of the
// candidate, else a point resampled along the ray, else the background
// direction), stored for the reprojection pass with the stream's state.
fn reprojection_source(index: u32, ray: Ray, r: ptr<function, Reservoir>,
                       rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) {
    let u0 = pcg32_next_f32(rng);
    let u1 = pcg32_next_f32(rng);
    var seen = vec4<f32>(0.0, 0.0, 0.0, -1.0);
    if (rp.reprojection != 0u) {
        var t = NO_HIT;
        if ((*r).has_y && (*r).y.k >= 1u) {
            t = (*r).y.z[0];
        } else if (rp.velocity_resampling != 0u) {
            t = resample_point(ray, rng, lookups);
        }
        if (t >= 0.0) {
            // Moved back along the velocity for one frame, then into the
            // medium's index space: the reprojection pass maps it out
            // through the previous frame's placement (rigid motion).
            let m = media[0];
            let x = ray_at(ray, t);
            let o = vec4<f32>(x - velocity_at(x) * rp.frame_dt, 1.0);
            seen = vec4<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o), 1.0);
        } else {
            seen = vec4<f32>(ray.d, 0.0);
        }
    }
    reservoirs[index].seen = seen;
    reservoirs[index].aux = vec4<f32>(u0, u1, 0.0, 0.0);
    reservoirs[index].rng = vec4<u32>((*rng).state, (*rng).inc);
}

@compute @workgroup_size(8, 8, 1)
fn candidates(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height || gid.z >= rp.batch) {
        return;
    }
    let pixel = gid.y * frame.width + gid.x;
    let sequence = rp.first_sequence + gid.z;
    let index = slot(rp.region_cand, gid.z, pixel);
    let ray = centre_ray(gid.x, gid.y);
    var rng = pass_rng(pixel, sequence, 0u);
    var lookups = 0u;
    var res = empty_reservoir();
    for (var j = 0u; j < rp.candidates; j++) {
        res.m += 1.0;
        walk(ray, &rng, &res, &lookups);
    }
    if (res.has_y) {
        var y = res.y;
        let p_hat = p_hat_of(ray, &y, &lookups);
        res_retarget(&res, p_hat);
    }
    store_reservoir(index, &res);
    if (rp.temporal != 0u) {
        var trng = pass_rng(pixel, sequence, 1u);
        reprojection_source(index, ray, &res, &trng, &lookups);
    }
    reservoirs[index].head.w = lookups;
}

// Integrator `visopt` (integrators/visopt/integrator.rs), Lerzer and Dachsbacher 2025 §5.4:
// delta tracking through μ' (Eq. 8) of the pixel's frozen camera list
// (built on the CPU, CameraLists), emission and next-event estimation
// toward one light picked by power — ratio tracking through μ' of a fresh
// NEE list when light_samples > 0 — with HG plus the gradient lobe at NEE;
// with scattering first/all the path goes on by HG sampling through the
// original μ, NEE optimised only with all.
//
// The CPU's first vertex (`sample`) and later ones (`continue_path`) are
// one vertex loop here, and collisions and transmittance one walk, so the
// optimised lookup and NEE appear once in the kernel: lavapipe inlines
// every call, and each copy costs compile time.

const WALK_COLLISION: u32 = 0u;
const WALK_TRANSMITTANCE: u32 = 1u;

// delta_tracking::sample (WALK_COLLISION: the collision's t, or NO_HIT) or
// ratio_tracking::transmittance (WALK_TRANSMITTANCE) over super-voxel
// majorants, through μ' of list `l` when `optimised` (μ' ≤ μ, so the
// majorants still bound it; Optimised::sigma_t) and through μ otherwise.
// `r` is the index-space ray, `world` the world ray with its parameter.
fn visopt_walk(m: MediumGpu, r: Ray, world: Ray, t0: f32, t1: f32, l: RayList, optimised: bool,
               mode: u32, rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> f32 {
    var tr = 1.0;
    var dda = dda_new(r, m.sv_size, m.sv_dims, t0, t1);
    var s: DdaStep;
    while (dda_next(&dda, &s)) {
        let sigma_maj = supervoxel(m, s.cell).y;
        if (sigma_maj <= 0.0) {
            continue;
        }
        var t = s.t0;
        loop {
            t += -log(1.0 - pcg32_next_f32(rng)) / sigma_maj;
            if (t >= s.t1) {
                break;
            }
            var sigma_t = sigma_t_at(m, ray_at(r, t), rng, lookups);
            if (optimised && sigma_t > 0.0) {
                sigma_t *= list_factor(l, t, ray_at(world, t), sigma_t);
            }
            if (mode == WALK_COLLISION) {
                if (pcg32_next_f32(rng) * sigma_maj < sigma_t) {
                    return t;
                }
            } else {
                tr *= null_probability(sigma_t, sigma_maj);
                if (tr == 0.0) {
                    return 0.0;
                }
            }
        }
    }
    if (mode == WALK_COLLISION) {
        return NO_HIT;
    }
    return tr;
}

// VisOpt::next_event: L_i f T / pdf toward one light picked by power;
// `slot` is the invocation's scratch slot for the NEE list.
fn visopt_next_event(p: vec3<f32>, d: vec3<f32>, optimise: bool, slot: u32,
                     rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> vec3<f32> {
    let u_pick = pcg32_next_f32(rng);
    if (env.pickable == 0u) {
        return vec3<f32>(0.0);
    }
    let picked = pick_light(u_pick, false, p);
    if (picked.index == NO_LIGHT) {
        return vec3<f32>(0.0);
    }
    let light = lights[picked.index];
    let pmf = picked.pmf;
    let u0 = pcg32_next_f32(rng);
    let u1 = pcg32_next_f32(rng);
    let ls = light_sample_li(light, p, u0, u1);
    if (!ls.valid) {
        return vec3<f32>(0.0);
    }
    let f = dvr_phase(p, d, ls.wi);
    var world: Ray;
    world.o = p;
    world.d = ls.wi;
    if (f <= 0.0 || all(ls.radiance == vec3<f32>(0.0)) || !visible(world, ls.distance)) {
        return vec3<f32>(0.0);
    }
    let m = media[0];
    var r: Ray;
    let range = to_index(m, world, ls.distance, &r);
    var tr = 1.0;
    if (range.z != 0.0) {
        let optimised = optimise && vo.light_samples > 0u;
        var l = RayList(LIST_LIGHT, 0u, 0u, 0.0, 0.0, 0.0, -1.0);
        if (optimised) {
            l = build_light_list(world, range.x, range.y, slot, rng);
        }
        tr = visopt_walk(m, r, world, range.x, range.y, l, optimised, WALK_TRANSMITTANCE, rng, lookups);
    }
    var pdf = pmf;
    if (!ls.is_delta) {
        pdf *= ls.pdf;
    }
    return ls.radiance * (f * tr / pdf);
}

// VisOpt::sample and continue_path: vertex 0 is found through μ' of the
// camera list, later ones (HG-sampled directions) through μ; NEE at every
// vertex, optimised at vertex 0 and, with scattering all, at every vertex;
// Russian roulette from vertex 3 on.
fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
    let m = media[0];
    let g = shading[0].w;
    let optimise = vo_flag(VISOPT_OPTIMISE);
    let slot = (y - frame.tile_y) * frame.width + x;
    var ray = primary_ray(x, y, pixel, sample);
    // The throughput is first · beta: vertex 0's albedo, and continue_path's
    // own throughput, which Russian roulette reads as on the CPU.
    var first = vec3<f32>(1.0);
    var beta = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var depth_max = vo.max_depth;
    if (vo.scattering == SCATTERING_SINGLE) {
        depth_max = 1u;
    }
    for (var depth = 0u; depth < depth_max; depth++) {
        var r: Ray;
        var range: vec3<f32>;
        var l = RayList(LIST_CAMERA, 0u, 0u, 0.0, 0.0, 0.0, 1.0);
        // Media end at the first surface (occluders.wgsl).
        let t_end = first_surface(ray);
        if (depth == 0u) {
            range = to_index_from_camera(m, ray, t_end, &r);
            let h = bitcast<vec4<u32>>(visopt_data[vo.lists_first + pixel]);
            l = RayList(LIST_CAMERA, h.x, h.y, bitcast<f32>(h.z), bitcast<f32>(h.w), range.x, 1.0);
        } else {
            range = to_index(m, ray, t_end, &r);
        }
        var t = NO_HIT;
        if (range.z != 0.0) {
            t = visopt_walk(m, r, ray, range.x, range.y, l, optimise && depth == 0u, WALK_COLLISION,
                            &rng, lookups);
        }
        if (t < 0.0) {
            if (depth == 0u && t_end == F32_INF) {
                radiance = escaped(ray.d, -1.0, false);
            }
            break;
        }
        let p = ray_at(ray, t);
        let albedo = albedo_at(0u, p);
        radiance += first * beta * emitted(0u, p, albedo);
        if (depth == 0u) {
            first = albedo;
        } else {
            beta *= albedo;
        }
        if (all(first * beta == vec3<f32>(0.0))) {
            break;
        }
        let optimise_nee = optimise && (depth == 0u || vo.scattering == SCATTERING_ALL);
        radiance += first * beta * visopt_next_event(p, ray.d, optimise_nee, slot, &rng, lookups);
        if (depth >= 3u) {
            let q = min(max(beta.x, max(beta.y, beta.z)), 1.0);
            if (pcg32_next_f32(&rng) >= q) {
                break;
            }
            beta /= q;
        }
        let u0 = pcg32_next_f32(&rng);
        let u1 = pcg32_next_f32(&rng);
        ray.o = p;
        ray.d = hg_sample(g, -ray.d, u0, u1).xyz;
    }
    return radiance;
}

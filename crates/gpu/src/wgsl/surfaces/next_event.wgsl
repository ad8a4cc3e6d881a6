// Next-event estimation among surfaces (integrators/shared/next_event.rs
// and free_flight.rs): shadow rays that stop at opaque surfaces, pass
// index-matched boundaries into the medium beyond and thin dielectrics
// with 1 − R′; the MIS weight of an emitting shape's radiance; the last
// vertex's sampled direction as a shadow query. Without shapes
// (INTEGRATOR_SURFACES off) these reduce to the media-only code the
// driver keeps.

// free_flight::shadow_transmittance_in: [0, distance] of `world` from
// bounded medium `current` (+ 1), for NEE at scattering vertex `vertex`.
fn shadow(world: Ray, distance: f32, vertex: u32, current: u32,
          rng: ptr<function, Pcg32>, lookups: ptr<function, u32>) -> vec3<f32> {
    if (!has_surfaces()) {
        return media_shadow(world, distance, vertex, current, rng, lookups);
    }
    if (!shadows_walk()) {
        if (bvh_trace(world.o, world.d, distance, true, true).slot != 0xffffffffu) {
            return vec3<f32>(0.0);
        }
        return media_shadow(world, distance, vertex, current, rng, lookups);
    }
    var ray = world;
    var left = distance;
    var medium = current;
    var tr = vec3<f32>(1.0);
    for (var i = 0u; i < MAX_CROSSINGS; i++) {
        let h = intersect_surfaces(ray.o, ray.d, left, false);
        if (!h.valid) {
            return tr * media_shadow(ray, left, vertex, medium, rng, lookups);
        }
        let passed = material_null_transmission(h, dot(h.ns, ray.d));
        if (passed < 0.0) {
            return vec3<f32>(0.0);
        }
        tr *= passed * media_shadow(ray, h.t, vertex, medium, rng, lookups);
        if (all(tr == vec3<f32>(0.0))) {
            return vec3<f32>(0.0);
        }
        medium = target_medium(h, ray.d, medium);
        left -= h.t;
        ray = Ray(spawn_origin(h, ray.d), ray.d);
    }
    return vec3<f32>(0.0);
}

// next_event::emitter_weight: the balance heuristic of an emitting
// triangle's radiance reached at q along d from the vertex prev_p, whose
// direction had solid-angle pdf prev_pdf (< 0: no light strategy could
// have produced it, weight 1).
fn emitter_weight(li: u32, q: vec3<f32>, d: vec3<f32>, prev_p: vec3<f32>, prev_pdf: f32,
                  prev_surface: bool) -> f32 {
    let l = lights[li];
    if (prev_pdf < 0.0 || !is_shape_light(l)) {
        return 1.0;
    }
    return balance(prev_pdf, light_pmf_at(li, prev_surface, prev_p) * shape_pdf_solid(l, prev_p, q, d));
}

// next_event::sampled_direction_to_lights as a shadow query: the last
// vertex's sampled direction (pdf < 0 for a delta lobe) is not traced; the
// first opaque surface along it gives its emission (MIS-weighted) or
// blocks; with none, the environment. `origin` is the vertex (the ray may
// start just off a surface).
fn direction_query(origin: vec3<f32>, ray: Ray, pdf: f32, surface: bool, current: u32) -> ShadowQuery {
    var q = no_query();
    q.ray = ray;
    q.medium = current;
    q.den = 0.0;
    if (has_surfaces()) {
        let h = intersect_surfaces(ray.o, ray.d, F32_INF, true);
        if (h.valid) {
            let e = surface_emitted(h, ray.d);
            q.valid = e.valid;
            q.le = e.le;
            q.w = emitter_weight(e.light, h.p, ray.d, origin, pdf, surface);
            q.distance = h.t * (1.0 - SHADOW_SHORTEN);
            return q;
        }
    }
    if (!has_environment()) {
        return q;
    }
    q.le = escaped(ray.d, pdf, surface);
    q.valid = any(q.le != vec3<f32>(0.0));
    q.w = -1.0;
    q.distance = F32_INF;
    return q;
}

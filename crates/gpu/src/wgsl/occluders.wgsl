// render::integrators::shared::occluders: shapes as opaque black occluders
// for the integrators without surface rules (point_mis, visopt, ament),
// and restir's visibility (its surface vertices: restir/surface.wgsl). A
// pipeline constant: without shapes the driver compiles the BVH walk out.
override OCCLUDERS: bool = false;

// occluders::first_surface: the distance to the first opaque surface.
fn first_surface(r: Ray) -> f32 {
    if (!OCCLUDERS) {
        return F32_INF;
    }
    let h = bvh_trace(r.o, r.d, F32_INF, false, true);
    return select(h.t, F32_INF, h.slot == 0xffffffffu);
}

// occluders::visible: no opaque surface cuts the ray in (0, t).
fn visible(r: Ray, t: f32) -> bool {
    if (!OCCLUDERS) {
        return true;
    }
    return bvh_trace(r.o, r.d, t, true, true).slot == 0xffffffffu;
}

// fogbank_render::integrators::restir::surface on the GPU (Lin et al. 2021 §4.2):
// a path vertex on a surface is the closest opaque surface along
// its segment, wherever reuse moves that segment; its factor in F and p̂ is
// f_s·|cos θ_i| of the side the arriving path sees (twosided in the
// mirrored frame, as TwoSided and the scatter kernel's vertices).

// The BSDF of the side seen along d, its frame, and wo in it.
struct SurfaceSide {
    bsdf: Bsdf,
    sf: ShadingFrame,
    back: bool,
    wo: vec3<f32>,
}

fn surface_side(h: Hit, d: vec3<f32>) -> SurfaceSide {
    let sf = shading_frame(h.ns);
    let wo = to_local(sf, -d);
    let back = is_two_sided(h.shape) && wo.z < 0.0;
    return SurfaceSide(surface_bsdf(h, back), sf, back, select(wo, flip_z(wo), back));
}

// SurfaceVertex::scatter: f_s·|cos θ_i| for light leaving along wi toward
// where the path arrived from along d.
fn surface_scatter(h: Hit, d: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let s = surface_side(h, d);
    var l = to_local(s.sf, wi);
    l = select(l, flip_z(l), s.back);
    return bsdf_eval(s.bsdf, s.wo, l) * abs(l.z);
}

// The scattering factor at vertex x (on surface h when `surface`): the
// phase function, or f_s·|cos θ|.
fn vertex_scatter(surface: bool, h: Hit, g: f32, d: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if (surface) {
        return surface_scatter(h, d, wi);
    }
    return vec3<f32>(hg_pdf(g, -d, wi));
}

// SurfaceVertex::leave: a segment leaving vertex x along w (pushed off the
// surface when on one).
fn vertex_leave(surface: bool, h: Hit, x: vec3<f32>, w: vec3<f32>) -> Ray {
    var r: Ray;
    r.o = select(x, spawn_origin(h, w), surface);
    r.d = w;
    return r;
}

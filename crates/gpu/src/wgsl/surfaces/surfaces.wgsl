// The scene's shapes (render/src/world/surfaces/scene_surfaces.rs): closest
// hits with their shading data, the material at a hit (texture looked up,
// Mitsuba's twosided), medium transitions, and the emission of a hit. The
// buffer layout is fogbank-gpu's surfaces.rs.

// The bindings and triangle records are surface_data.wgsl's.

fn has_surfaces() -> bool {
    return (INTEGRATOR_FLAGS & INTEGRATOR_SURFACES) != 0u;
}

// Shadow rays walk surface to surface (some shape bounds a medium or
// passes part of the light): Surfaces::shadows_walk.
fn shadows_walk() -> bool {
    return surface_word(1u, 0u) != 0u;
}

// The bounded medium the camera starts in, + 1 (0: none).
fn camera_medium() -> u32 {
    if (!has_surfaces()) {
        return 0u;
    }
    return surface_word(0u, 3u);
}

// World::medium_active: medium i exists for a ray in bounded medium
// `current` (+ 1) unless shapes bound it and the ray is not inside.
fn medium_active(i: u32, current: u32) -> bool {
    if (!has_surfaces() || current == i + 1u) {
        return true;
    }
    return surface_word(2u + i / 4u, i % 4u) == 0u;
}

fn shape_base(shape: u32) -> u32 {
    return surface_word(0u, 0u) + shape * SHAPE_STRIDE;
}

fn shape_flags(shape: u32) -> u32 {
    return surface_word(shape_base(shape) + 1u, 0u);
}

struct Hit {
    valid: bool,
    t: f32,
    p: vec3<f32>,
    // Unit geometric normal (the winding's) and shading normal.
    ng: vec3<f32>,
    ns: vec3<f32>,
    uv: vec2<f32>,
    shape: u32,
    // The primitive's index (triangle of the scene mesh, or analytic
    // shape after them; of its group's for a shape of a group, which
    // never emits), for its light.
    primitive: u32,
    // Its leaf slot in the concatenated records.
    slot: u32,
}

fn no_hit() -> Hit {
    return Hit(false, 0.0, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec2<f32>(0.0), 0u, 0u, 0u);
}

// Surfaces::intersect (opaque = false) and intersect_opaque: the closest
// surface in (0, t_max) with its shading data (Surfaces::hit), a hit in an
// instance's group placed in the world (shape_groups::to_world).
fn intersect_surfaces(o: vec3<f32>, d: vec3<f32>, t_max: f32, opaque: bool) -> Hit {
    if (!has_surfaces()) {
        return no_hit();
    }
    let s = bvh_trace(o, d, t_max, false, opaque);
    if (s.slot == 0xffffffffu) {
        return no_hit();
    }
    if (s.instance == 0xffffffffu) {
        return surface_hit(s, o, d);
    }
    let r = instance_object_ray(s.instance, o, d);
    return instance_to_world(s.instance, surface_hit(s, r.o, r.d));
}

// The group → world placement of a hit in an instance's group: the point by
// the instance's map, normals by the inverse transpose, the winding's
// normal turned when the map mirrors (an analytic shape's normal is its
// surface normal, placed as such).
fn instance_to_world(i: u32, h_in: Hit) -> Hit {
    var h = h_in;
    let b = instance_record(i);
    h.p = affine_point(b + 3u, h.p);
    let r0 = surface_data[b].xyz;
    let r1 = surface_data[b + 1u].xyz;
    let r2 = surface_data[b + 2u].xyz;
    let ng = normalize(h.ng.x * r0 + h.ng.y * r1 + h.ng.z * r2);
    if (surface_is_analytic(h.slot)) {
        h.ng = ng;
        h.ns = ng;
        return h;
    }
    h.ng = select(ng, -ng, surface_word(b + 6u, 2u) != 0u);
    let ns = h.ns.x * r0 + h.ns.y * r1 + h.ns.z * r2;
    if ((shape_flags(h.shape) & SHAPE_NORMALS) != 0u && dot(ns, ns) > 0.0) {
        h.ns = normalize(ns);
    } else {
        h.ns = h.ng;
    }
    return h;
}

// Surfaces::hit of the walk's hit `s` on the ray (o, d) in the space of
// the hierarchy it was found in.
fn surface_hit(s: SurfaceHit, o: vec3<f32>, d: vec3<f32>) -> Hit {
    let base = surface_word(0u, 1u) + 3u * s.slot;
    if (surface_is_analytic(s.slot)) {
        let a = analytic_hit(surface_analytic(s.slot), o, d, s.t);
        return Hit(true, s.t, a.p, a.n, a.n, a.uv, bitcast<u32>(surface_data[base].w),
                   surface_word(base + 1u, 3u) & ~PRIMITIVE_ANALYTIC, s.slot);
    }
    let c0 = surface_data[base];
    let c1 = surface_data[base + 1u];
    let c2 = surface_data[base + 2u];
    let b = vec3<f32>(1.0 - s.b1 - s.b2, s.b1, s.b2);
    var h: Hit;
    h.valid = true;
    h.t = s.t;
    h.slot = s.slot;
    h.shape = bitcast<u32>(c0.w);
    h.primitive = bitcast<u32>(c1.w);
    // The barycentric point, not o + t d: it lies on the triangle.
    h.p = b.x * c0.xyz + b.y * c1.xyz + b.z * c2.xyz;
    let all_finite = finite(h.p.x) && finite(h.p.y) && finite(h.p.z);
    h.p = select(o + s.t * d, h.p, all_finite);
    let n = cross(c1.xyz - c0.xyz, c2.xyz - c0.xyz);
    h.ng = select(vec3<f32>(0.0), normalize(n), dot(n, n) > 0.0);
    let flags = shape_flags(h.shape);
    let sh = surface_word(0u, 2u) + 4u * s.slot;
    let v0 = surface_data[sh];
    let v1 = surface_data[sh + 1u];
    let v2 = surface_data[sh + 2u];
    let v3 = surface_data[sh + 3u];
    h.ns = h.ng;
    if ((flags & SHAPE_NORMALS) != 0u) {
        let ns = b.x * v0.xyz + b.y * v1.xyz + b.z * v2.xyz;
        if (dot(ns, ns) > 0.0) {
            h.ns = normalize(ns);
        }
    }
    if ((flags & SHAPE_UVS) != 0u) {
        h.uv = b.x * vec2<f32>(v0.w, v1.w) + b.y * vec2<f32>(v2.w, v3.x) + b.z * v3.yz;
    } else {
        // Mitsuba's default parameterisation of a mesh without UVs.
        h.uv = vec2<f32>(s.b1, s.b2);
    }
    return h;
}

// scene_surfaces::offset: p moved off the surface toward the side of d.
fn spawn_origin(h: Hit, d: vec3<f32>) -> vec3<f32> {
    let eps = 1e-5 * (1.0 + max(abs(h.p.x), max(abs(h.p.y), abs(h.p.z))));
    return h.p + h.ng * select(-eps, eps, dot(h.ng, d) >= 0.0);
}

// Surfaces::target_medium: the medium (+ 1) a ray leaving h along w is in.
fn target_medium(h: Hit, w: vec3<f32>, current: u32) -> u32 {
    let r = surface_data[shape_base(h.shape)];
    let interior = bitcast<u32>(r.x);
    let exterior = bitcast<u32>(r.y);
    if (interior == exterior) {
        return current;
    }
    return select(interior, exterior, dot(w, h.ng) > 0.0);
}

struct Emitted {
    le: vec3<f32>,
    light: u32,
    valid: bool,
}

// Surfaces::emitted: the radiance toward -d on the emitting side (the
// shading normal's) and the index of the primitive's light.
fn surface_emitted(h: Hit, d: vec3<f32>) -> Emitted {
    let base = shape_base(h.shape);
    if ((shape_flags(h.shape) & SHAPE_EMITS) == 0u || dot(h.ns, d) >= 0.0) {
        return Emitted(vec3<f32>(0.0), 0u, false);
    }
    let r = surface_data[base];
    let light = bitcast<u32>(r.z) + h.primitive - bitcast<u32>(r.w);
    return Emitted(surface_data[base + 2u].xyz, light, true);
}

fn shape_is_null(shape: u32) -> bool {
    return (shape_flags(shape) & SHAPE_NULL) != 0u;
}

// Texture::eval of a side record's texture at uv (checkerboard: color0
// where both coordinates are in the same half of their period; bitmap:
// bitmap.wgsl).
fn side_texture(base: u32, uv_in: vec2<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let kind = surface_word(base, 3u) >> 8u;
    if (kind == TEXTURE_CONSTANT) {
        return fallback;
    }
    let c0 = surface_data[base + 4u];
    let c1 = surface_data[base + 5u];
    let m = surface_data[base + 6u];
    let uv = vec2<f32>(m.x * uv_in.x + m.z * uv_in.y + c0.w, m.y * uv_in.x + m.w * uv_in.y + c1.w);
    if (kind == TEXTURE_BITMAP) {
        return bitmap_eval(bitcast<vec3<u32>>(c0.xyz), bitcast<u32>(c1.x), uv);
    }
    let f = uv - floor(uv);
    return select(c1.xyz, c0.xyz, (f.x > 0.5) == (f.y > 0.5));
}

// Side::at: the side's model with its texture in place of the parameter
// it replaces (diffuse reflectance, plastic base, conductor tint).
fn side_bsdf(base: u32, uv: vec2<f32>) -> Bsdf {
    let h = surface_data[base];
    var b: Bsdf;
    b.kind = bitcast<u32>(h.x);
    let flags = bitcast<u32>(h.w);
    b.mf = Microfacet(h.y, (flags & 2u) != 0u, (flags & 4u) == 0u);
    b.eta = h.z;
    b.nonlinear = (flags & 1u) != 0u;
    b.a = surface_data[base + 1u].xyz;
    b.b = surface_data[base + 2u].xyz;
    let c = surface_data[base + 3u];
    b.c = c.xyz;
    b.internal = c.x;
    b.coating = bitcast<u32>(c.y);
    if (b.kind == BSDF_CONDUCTOR) {
        b.c = side_texture(base, uv, b.c);
    } else {
        b.a = side_texture(base, uv, b.a);
    }
    return b;
}

// A hit's material (Mitsuba's twosided: the back side seen in the mirrored
// frame): whether it has a back side, the record of the side a direction
// with cosine c (to the shading normal) meets, and that side's BSDF.
fn is_two_sided(shape: u32) -> bool {
    return (shape_flags(shape) & SHAPE_TWO_SIDED) != 0u;
}

fn side_base(shape: u32, back: bool) -> u32 {
    return shape_base(shape) + 3u + select(0u, SIDE_STRIDE, back);
}

fn surface_bsdf(h: Hit, back: bool) -> Bsdf {
    return side_bsdf(side_base(h.shape, back), h.uv);
}

// SurfaceBsdf::is_delta: every lobe of both sides is a delta.
fn material_is_delta(shape: u32) -> bool {
    let front = side_bsdf(side_base(shape, false), vec2<f32>(0.0));
    if (!is_two_sided(shape)) {
        return bsdf_is_delta(front);
    }
    return bsdf_is_delta(front) && bsdf_is_delta(side_bsdf(side_base(shape, true), vec2<f32>(0.0)));
}

// Material::null_transmission at cosine c with the shading normal (-1: none).
fn material_null_transmission(h: Hit, c: f32) -> f32 {
    return bsdf_null_transmission(surface_bsdf(h, is_two_sided(h.shape) && c < 0.0), c);
}

// TwoSided's mirror through the surface (local frame).
fn flip_z(w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(w.x, w.y, -w.z);
}

// ShadingFrame::new (glam's any_orthonormal_pair, Duff et al. 2017).
struct ShadingFrame {
    s: vec3<f32>,
    t: vec3<f32>,
    n: vec3<f32>,
}

fn shading_frame(n: vec3<f32>) -> ShadingFrame {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return ShadingFrame(vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
                        vec3<f32>(b, sign + n.y * n.y * a, -n.y), n);
}

fn to_local(f: ShadingFrame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f.s), dot(v, f.t), dot(v, f.n));
}

fn to_world(f: ShadingFrame, v: vec3<f32>) -> vec3<f32> {
    return f.s * v.x + f.t * v.y + f.n * v.z;
}

// Medium properties at scattering vertices (render/src/field.rs,
// emission.rs, blackbody.rs, SceneMedium::albedo_at / emitted): albedo
// grids, emission (colour × grid, or a blackbody of a temperature grid).
// Property grids are records of the media buffer after the scene's media.

// Per medium i: shading[i] = (albedo, g); from env.props_ext on, three
// vec4 per medium as in lights.rs (medium_ext); from env.props_blackbody
// on, the blackbody table: (first kelvin, step, count, 0), then
// linear-sRGB rows.
@group(2) @binding(4) var<storage, read> shading: array<vec4<f32>>;

fn medium_ext(k: u32) -> vec4<f32> {
    return shading[env.props_ext + k];
}

fn blackbody(k: u32) -> vec4<f32> {
    return shading[env.props_blackbody + k];
}

// Field::eval: trilinear value(s) at world point p, zero outside the box.
fn field_eval(first: u32, channels: u32, p: vec3<f32>) -> vec3<f32> {
    var out = vec3<f32>(0.0);
    for (var c = 0u; c < channels; c++) {
        let m = media[first + c];
        let o = vec4<f32>(p, 1.0);
        let q = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
        if (any(q < vec3<f32>(0.0)) || any(q > vec3<f32>(m.dims))) {
            return vec3<f32>(0.0);
        }
        out[c] = trilinear(m, q);
    }
    if (channels == 1u) {
        return vec3<f32>(out.x);
    }
    return out;
}

// SceneMedium::scalar_at: the density's stored value, trilinear, 0 outside.
fn scalar_at(m: MediumGpu, p: vec3<f32>) -> f32 {
    let o = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
    if (any(q < vec3<f32>(0.0)) || any(q > vec3<f32>(m.dims))) {
        return 0.0;
    }
    return trilinear(m, q);
}

fn albedo_at(mi: u32, p: vec3<f32>) -> vec3<f32> {
    let a = shading[mi].xyz;
    let m = media[mi];
    let colours = m.tf_counts >> 16u;
    if (colours != 0u) {
        let offset = m.tf_offset + 2u * (m.tf_counts & 0xffffu);
        return clamp(a * pl_rgb(offset, colours, scalar_at(m, p)), vec3<f32>(0.0), vec3<f32>(1.0));
    }
    let ext = medium_ext(3u * mi);
    if (ext.x == 0.0) {
        return a;
    }
    return clamp(a * field_eval(u32(ext.x) - 1u, u32(ext.y), p), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn blackbody_rgb(t: f32) -> vec3<f32> {
    let h = blackbody(0u);
    if (!(t > h.x)) {
        return vec3<f32>(0.0);
    }
    let n = u32(h.z);
    let x = min((t - h.x) / h.y, f32(n - 1u));
    let i = min(u32(x), n - 2u);
    let w = x - f32(i);
    return blackbody(1u + i).xyz * (1.0 - w) + blackbody(2u + i).xyz * w;
}

// SceneMedium::emitted: (1 − albedo) L_e.
fn emitted(mi: u32, p: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    let m = media[mi];
    if (m.tf_emission != 0u) {
        let offset = m.tf_offset + 2u * (m.tf_counts & 0xffffu) + 4u * (m.tf_counts >> 16u);
        return (vec3<f32>(1.0) - albedo) * pl_rgb(offset, m.tf_emission, scalar_at(m, p));
    }
    let ext = medium_ext(3u * mi);
    let e = medium_ext(3u * mi + 1u);
    var le = e.xyz;
    switch u32(ext.z) {
        case EMISSION_NONE: {
            return vec3<f32>(0.0);
        }
        case EMISSION_COLOR: {
            if (ext.w != 0.0) {
                le *= max(field_eval(u32(ext.w) - 1u, 1u, p), vec3<f32>(0.0));
            }
        }
        case EMISSION_BLACKBODY: {
            let offset = medium_ext(3u * mi + 2u).x;
            le *= blackbody_rgb((field_eval(u32(ext.w) - 1u, 1u, p).x - offset) * e.w);
        }
        default: {
            invalid_id();
            return vec3<f32>(0.0);
        }
    }
    return (vec3<f32>(1.0) - albedo) * le;
}

// Chromatic extinction (world/chroma.rs): the record + 1 of medium mi's
// first channel medium (0: achromatic), from medium_ext's third row.
fn chroma_first(mi: u32) -> u32 {
    return u32(medium_ext(3u * mi + 2u).y);
}

// Whether the channels' k varies in space (per-channel grids).
fn chroma_varying(mi: u32) -> bool {
    return medium_ext(3u * mi + 2u).z != 0.0;
}

// Chroma::k of constant ratios: each channel's scale over the tracked one's.
fn chroma_k(mi: u32, first: u32) -> vec3<f32> {
    return vec3<f32>(media[first - 1u].scale, media[first].scale, media[first + 1u].scale)
        / media[mi].scale;
}

// Medium::sigma_t_smooth at index point q: trilinear, 0 outside [0, dims].
fn sigma_t_smooth(m: MediumGpu, q: vec3<f32>) -> f32 {
    if (any(q < vec3<f32>(0.0)) || any(q > vec3<f32>(m.dims))) {
        return 0.0;
    }
    return m.scale * classify(m, trilinear(m, q));
}

// Chroma::k_at: each channel's extinction over the tracked channel's at a
// collision at world point p (constant: the ratio of their scales).
fn chroma_k_at(mi: u32, first: u32, p: vec3<f32>, lookups: ptr<function, u32>) -> vec3<f32> {
    if (!chroma_varying(mi)) {
        return chroma_k(mi, first);
    }
    let m = media[mi];
    let r = media[first - 1u];
    let g = media[first];
    let b = media[first + 1u];
    let o = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(m.w2i0, o), dot(m.w2i1, o), dot(m.w2i2, o));
    *lookups += 4u;
    let tracked = sigma_t_smooth(m, q);
    if (!(tracked > 0.0)) {
        return vec3<f32>(0.0);
    }
    // ≤ 1 but for rounding: the tracked grid bounds each channel's.
    let k = vec3<f32>(sigma_t_smooth(r, q), sigma_t_smooth(g, q), sigma_t_smooth(b, q)) / tracked;
    return min(k, vec3<f32>(1.0));
}

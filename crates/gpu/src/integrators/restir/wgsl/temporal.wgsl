// fogbank_render::integrators::restir::temporal on the GPU (Lin et al. 2021 §4.4,
// §5.2), in two passes. `reproject` runs with the previous frame's data
// (camera, medium placement, lights): it maps what the pixel saw (stored
// by the candidate pass) out through the previous placement, projects it
// with the previous camera, picks one of the four nearest pixels with
// bilinear probability (off screen: the same pixel), and evaluates the
// previous pixel's target at the candidate's sample, p̂_prev(x). `temporal`
// runs with the current frame's data and combines the candidate reservoir
// with the previous frame's final one at that pixel, M capped at Q·M, with
// the stream the candidate pass left.

// The inverse of a medium's world → index map (rows w2i0..2).
fn index_to_world(m: MediumGpu, q: vec3<f32>) -> vec3<f32> {
    let r0 = m.w2i0.xyz;
    let r1 = m.w2i1.xyz;
    let r2 = m.w2i2.xyz;
    let v = q - vec3<f32>(m.w2i0.w, m.w2i1.w, m.w2i2.w);
    let c0 = cross(r1, r2);
    let det = dot(r0, c0);
    return (c0 * v.x + cross(r2, r0) * v.y + cross(r0, r1) * v.z) / det;
}

// Camera::project: the film position of p (z = 1), or z = 0 behind the camera.
fn project(p: vec3<f32>) -> vec3<f32> {
    let v = p - frame.cam_origin.xyz;
    let z = dot(v, frame.cam_forward.xyz);
    if (!(z > 0.0)) {
        return vec3<f32>(0.0);
    }
    let sx = dot(v, frame.cam_right.xyz) / (z * frame.tan_half.x);
    let sy = dot(v, frame.cam_up.xyz) / (z * frame.tan_half.y);
    let xy = vec2<f32>(0.5 * (sx + 1.0) * f32(frame.width), 0.5 * (1.0 - sy) * f32(frame.height));
    if (!is_finite1(xy.x) || !is_finite1(xy.y)) {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(xy, 1.0);
}

@compute @workgroup_size(8, 8, 1)
fn reproject(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height || gid.z >= rp.batch) {
        return;
    }
    let pixel = gid.y * frame.width + gid.x;
    let index = slot(rp.region_cand, gid.z, pixel);
    let s = reservoirs[index];
    var source = vec2<u32>(gid.x, gid.y);
    if (s.seen.w >= 0.0) {
        var p: vec3<f32>;
        if (s.seen.w > 0.5) {
            p = project(index_to_world(media[0], s.seen.xyz));
        } else {
            p = project(frame.cam_origin.xyz + s.seen.xyz);
        }
        if (p.z != 0.0) {
            let fx = floor(p.x - 0.5 + s.aux.x);
            let fy = floor(p.y - 0.5 + s.aux.y);
            if (fx >= 0.0 && fy >= 0.0 && fx < f32(frame.width) && fy < f32(frame.height)) {
                source = vec2<u32>(u32(fx), u32(fy));
            }
        }
    }
    var lookups = 0u;
    var p_prev = 0.0;
    if (((s.head.x >> 16u) & 1u) != 0u) {
        var y = load_reservoir(index).y;
        p_prev = p_hat_of(centre_ray(source.x, source.y), &y, &lookups);
    }
    reservoirs[index].head.z = source.y * frame.width + source.x;
    reservoirs[index].w.w = p_prev;
    reservoirs[index].head.w = s.head.w + lookups;
}

@compute @workgroup_size(8, 8, 1)
fn temporal(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height || gid.z >= rp.batch) {
        return;
    }
    let pixel = gid.y * frame.width + gid.x;
    let index = slot(rp.region_cand, gid.z, pixel);
    let s = reservoirs[index];
    var rng = Pcg32(s.rng.xy, s.rng.zw);
    var lookups = s.head.w;
    set_input(0u, index, pixel, 0.0);
    set_input(1u, slot(rp.region_prev, gid.z, s.head.z), s.head.z, rp.temporal_cap * s.w.y);
    combining_temporal = true;
    temporal_p_hat_prev = s.w.w;
    var out = combine(2u, &rng, &lookups);
    let o = slot(rp.region_temporal, gid.z, pixel);
    store_reservoir(o, &out);
    reservoirs[o].head.w = lookups;
}

// fogbank_render::integrators::restir::{spatial, neighbours} on the GPU
// (Lin et al. 2021 §4.3, §5.3): one round over the pixel and its neighbours from
// the R2 sequence (points in `rp.r2`, from the Rust definition), rotated
// per pixel and frame by a hash, uniform in the disk of `radius` pixels;
// neighbours off the screen are skipped.

fn r2_point(k: u32) -> vec2<f32> {
    let v = rp.r2[k / 2u];
    if ((k & 1u) == 0u) {
        return v.xy;
    }
    return v.zw;
}

// f32::round: half away from zero.
fn round_away(x: f32) -> i32 {
    return i32(sign(x) * floor(abs(x) + 0.5));
}

// neighbours::neighbour_offset: never (0, 0).
fn neighbour_offset(pixel: u32, frame_index: u32, k: u32, radius: f32) -> vec2<i32> {
    let h = pcg3d(vec3<u32>(pixel, frame_index, 0x5E571A7Fu));
    let shift = vec2<f32>(unit_f32(h.x), unit_f32(h.y));
    let p = r2_point(k);
    for (var attempt = 0u; attempt < 8u; attempt++) {
        let u = fract(p.x + shift.x + f32(attempt) * 0.618034);
        let v = fract(p.y + shift.y);
        let r = radius * sqrt(u);
        let phi = 2.0 * PI * v;
        let o = vec2<i32>(round_away(r * cos(phi)), round_away(r * sin(phi)));
        if (o.x != 0 || o.y != 0) {
            return o;
        }
    }
    return vec2<i32>(1, 0);
}

@compute @workgroup_size(8, 8, 1)
fn spatial(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height || gid.z >= rp.batch) {
        return;
    }
    let pixel = gid.y * frame.width + gid.x;
    let sequence = rp.first_sequence + gid.z;
    let index = slot(rp.region_spatial_in, gid.z, pixel);
    var rng = pass_rng(pixel, sequence, 2u);
    var lookups = reservoirs[index].head.w;
    set_input(0u, index, pixel, 0.0);
    var n = 1u;
    for (var k = 0u; k < rp.neighbours; k++) {
        let o = neighbour_offset(pixel, rp.frame_index, k, rp.radius);
        let x = i32(gid.x) + o.x;
        let y = i32(gid.y) + o.y;
        if (x < 0 || y < 0 || x >= i32(frame.width) || y >= i32(frame.height)) {
            continue;
        }
        let q = u32(y) * frame.width + u32(x);
        set_input(n, slot(rp.region_spatial_in, gid.z, q), q, 0.0);
        n++;
    }
    combining_temporal = false;
    var out = combine(n, &rng, &lookups);
    let o = slot(rp.region_spatial_out, gid.z, pixel);
    store_reservoir(o, &out);
    reservoirs[o].head.w = lookups;
}

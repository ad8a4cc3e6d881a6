// Restir::shade on the GPU (Eq. 21): F(y)·W with the shading estimator on
// every segment at full resolution; then `reduce` adds each pixel's
// sequences of the batch to the accumulation buffers (every frame's
// lookups; the radiance of the frame being kept), as accumulate.wgsl does
// for the per-sample kernels.

@compute @workgroup_size(8, 8, 1)
fn shade(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height || gid.z >= rp.batch) {
        return;
    }
    let pixel = gid.y * frame.width + gid.x;
    let sequence = rp.first_sequence + gid.z;
    let index = slot(rp.region_final, gid.z, pixel);
    var rng = pass_rng(pixel, sequence, 3u);
    var lookups = 0u;
    sample_invalid = false;
    var r = load_reservoir(index);
    let w = contribution_weight(r.has_y, r.w_sum, r.m, r.p_hat);
    var l = vec3<f32>(0.0);
    if (r.has_y && w > 0.0) {
        var y = r.y;
        l = evaluate(centre_ray(gid.x, gid.y), &y, MODE_F, &rng, &lookups) * w;
    }
    reservoirs[index].shaded = vec4<f32>(l, select(0.0, 1.0, !sample_invalid));
    reservoirs[index].head.w += lookups;
}

@compute @workgroup_size(8, 8, 1)
fn reduce(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let pixel = gid.y * frame.width + gid.x;
    var m = moments_empty();
    var nonfinite = 0.0;
    var lookups = 0u;
    for (var s = 0u; s < rp.batch; s++) {
        let st = reservoirs[slot(rp.region_final, s, pixel)];
        lookups += st.head.w;
        let v = st.shaded.xyz;
        if (is_finite3(v) && st.shaded.w > 0.5) {
            moments_add(&m, v);
        } else {
            nonfinite += 1.0;
        }
    }
    if (rp.accumulate != 0u) {
        accumulate_moments(pixel, m, nonfinite);
    }
    accum_lookups[pixel] += lookups;
}

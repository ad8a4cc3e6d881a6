// The entry points every rendering kernel shares. `main`: per pixel of the
// band and chunk (grid z) of the dispatch, SAMPLES_PER_CHUNK samples of the
// kernel's `pixel_sample` in a row, finite ones folded into the chunk's mean
// and M2 and non-finite or invalid ones counted, written to the chunk's slot.
// `merge`: per pixel, the dispatch's chunks folded into the pixel's moments
// in chunk order — the same arithmetic as one chunk per dispatch, so an
// image does not depend on how many chunks ran side by side.

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let y = gid.y + frame.tile_y;
    if (gid.x >= frame.width || y >= frame.height || gid.z >= frame.chunks) {
        return;
    }
    let pixel = y * frame.width + gid.x;
    let first = gid.z * SAMPLES_PER_CHUNK;
    let count = min(SAMPLES_PER_CHUNK, frame.sample_count - first);
    var m = moments_empty();
    var lookups = 0u;
    var nonfinite = 0.0;
    for (var k = 0u; k < count; k++) {
        sample_invalid = false;
        let v = pixel_sample(pixel, gid.x, y, frame.first_sample + first + k, &lookups);
        if (is_finite3(v) && !sample_invalid) {
            moments_add(&m, v);
        } else {
            nonfinite += 1.0;
        }
    }
    let slot = 3u * (gid.z * frame.band_pixels + gid.y * frame.width + gid.x);
    accum_chunks[slot] = vec4<f32>(m.mean, m.n);
    accum_chunks[slot + 1u] = vec4<f32>(m.m2, nonfinite);
    accum_chunks[slot + 2u] = vec4<f32>(bitcast<f32>(lookups), 0.0, 0.0, 0.0);
}

@compute @workgroup_size(64, 1, 1)
fn merge(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= frame.band_pixels) {
        return;
    }
    let pixel = frame.tile_y * frame.width + i;
    var lookups = 0u;
    for (var c = 0u; c < frame.chunks; c++) {
        let slot = 3u * (c * frame.band_pixels + i);
        let a = accum_chunks[slot];
        let b = accum_chunks[slot + 1u];
        accumulate_moments(pixel, Moments(a.w, a.xyz, b.xyz), b.w);
        lookups += bitcast<u32>(accum_chunks[slot + 2u].x);
    }
    accum_lookups[pixel] += lookups;
}

// The entry point every rendering kernel shares: per pixel, `sample_count`
// samples of the kernel's `pixel_sample`, finite ones summed (with squares)
// and non-finite or invalid ones counted, added to the device accumulation buffers.

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let y = gid.y + frame.tile_y;
    if (gid.x >= frame.width || y >= frame.height) {
        return;
    }
    let pixel = y * frame.width + gid.x;
    var sum = vec3<f32>(0.0);
    var sq = vec3<f32>(0.0);
    var lookups = 0u;
    var count = 0.0;
    var nonfinite = 0.0;
    for (var k = 0u; k < frame.sample_count; k++) {
        sample_invalid = false;
        let v = pixel_sample(pixel, gid.x, y, frame.first_sample + k, &lookups);
        if (is_finite3(v) && !sample_invalid) {
            sum += v;
            sq += v * v;
            count += 1.0;
        } else {
            nonfinite += 1.0;
        }
    }
    accum_sum[pixel] += vec4<f32>(sum, count);
    accum_sq[pixel] += vec4<f32>(sq, nonfinite);
    accum_lookups[pixel] += lookups;
}

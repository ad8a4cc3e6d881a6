// The entry point every rendering kernel shares: per pixel, `sample_count`
// samples of the kernel's `pixel_sample`, finite ones merged into the
// pixel's running mean and M2 and non-finite or invalid ones counted.

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let y = gid.y + frame.tile_y;
    if (gid.x >= frame.width || y >= frame.height) {
        return;
    }
    let pixel = y * frame.width + gid.x;
    var m = moments_empty();
    var lookups = 0u;
    var nonfinite = 0.0;
    for (var k = 0u; k < frame.sample_count; k++) {
        sample_invalid = false;
        let v = pixel_sample(pixel, gid.x, y, frame.first_sample + k, &lookups);
        if (is_finite3(v) && !sample_invalid) {
            moments_add(&m, v);
        } else {
            nonfinite += 1.0;
        }
    }
    accumulate_moments(pixel, m, nonfinite);
    accum_lookups[pixel] += lookups;
}

// Integrator `transmittance` (seed 000 §6.1): per pixel and sample, the
// transmittance of the primary ray through all media times the background,
// accumulated on the device over `sample_count` samples per dispatch.

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= frame.width || gid.y >= frame.height) {
        return;
    }
    let pixel = gid.y * frame.width + gid.x;
    var sum = vec3<f32>(0.0);
    var sq = vec3<f32>(0.0);
    var lookups = 0u;
    var count = 0.0;
    var nonfinite = 0.0;
    for (var k = 0u; k < frame.sample_count; k++) {
        let sample = frame.first_sample + k;
        let world = primary_ray(gid.x, gid.y, pixel, sample);
        var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
        var tr = 1.0;
        for (var i = 0u; i < frame.media_count; i++) {
            let m = media[i];
            var r: Ray;
            let range = to_index_from_camera(m, world, F32_INF, &r);
            if (range.z != 0.0) {
                tr *= estimate(m, r, range.x, range.y, &rng, &lookups);
            }
        }
        let v = frame.background.xyz * tr;
        if (is_finite3(v)) {
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

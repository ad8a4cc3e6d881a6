// Integrator `test_tint` (test-only): per sample, the media's transmittance
// along the camera ray times the tint (frame.background), ramped across the
// image by the pixel's column, as the CPU's test_tint/mod.rs.

fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    let world = primary_ray(x, y, pixel, sample);
    var rng = sample_rng(frame.seed, pixel, sample, DIM_ESTIMATOR);
    var tr = 1.0;
    for (var i = 0u; i < frame.media_count; i++) {
        let m = media[i];
        var r: Ray;
        let range = to_index_from_camera(m, world, camera_ray_end(world), &r);
        if (range.z != 0.0) {
            tr *= estimate(m, r, range.x, range.y, &rng, lookups);
        }
    }
    let ramp = (f32(x) + 0.5) / f32(frame.width);
    return frame.background.xyz * (ramp * tr);
}

// Integrator `transmittance` (Peters 2025 §6.1): per sample, the
// transmittance of the primary ray through all media times the background.

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
    return frame.background.xyz * tr;
}

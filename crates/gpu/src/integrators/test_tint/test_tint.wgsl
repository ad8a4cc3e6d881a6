// Integrator `test_tint` (test-only): per sample, the media's transmittance
// along the camera ray times the tint (frame.background), ramped across the
// image by the pixel's column, as the CPU's test_tint/mod.rs.

fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    let ramp = (f32(x) + 0.5) / f32(frame.width);
    return frame.background.xyz * (ramp * camera_transmittance(pixel, x, y, sample, lookups));
}

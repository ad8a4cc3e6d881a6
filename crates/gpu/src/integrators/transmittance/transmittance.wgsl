// Integrator `transmittance` (Peters 2025 §6.1): per sample, the
// transmittance of the primary ray through all media times the background.

fn pixel_sample(pixel: u32, x: u32, y: u32, sample: u32, lookups: ptr<function, u32>) -> vec3<f32> {
    return frame.background.xyz * camera_transmittance(pixel, x, y, sample, lookups);
}

//! Shared by the GPU test binaries.

use fogbank_image::Image;
use fogbank_render::Film;

/// The film as an image for the z-test. The variance gets a floor of
/// (1e-5 · value)²: GPU rays are transformed in f32 (the CPU uses f64), so
/// a grazing ray can meet a near-empty voxel on one side only, and a pixel
/// that is exactly 1 on the CPU may be 0.9999996 on the GPU with no noise
/// on either side.
pub fn image(f: &Film) -> Image {
    let rgb = f.mean();
    let variance = f
        .variance_of_mean()
        .iter()
        .zip(&rgb)
        .map(|(v, m)| [0, 1, 2].map(|c| v[c].max((1e-5 * m[c]).powi(2))))
        .collect();
    Image {
        width: f.width as usize,
        height: f.height as usize,
        rgb,
        variance: Some(variance),
        is_srgb8: false,
    }
}

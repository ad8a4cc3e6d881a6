//! The per-pixel reductions under the pixel-wise metrics, and the size
//! check every metric starts with.

use crate::image_io::Image;

/// Errors unless both images have the same resolution and hold a pixel
/// array of that size; every metric starts with it.
pub fn check_same_size(reference: &Image, test: &Image) -> Result<(), String> {
    for (what, img) in [("reference", reference), ("test", test)] {
        if img.rgb.len() != img.width * img.height {
            return Err(format!(
                "{what} image holds {} pixels but claims {}×{}",
                img.rgb.len(),
                img.width,
                img.height
            ));
        }
        if let Some(v) = &img.variance {
            if v.len() != img.rgb.len() {
                return Err(format!(
                    "{what} image has {} variance pixels for {} colour pixels",
                    v.len(),
                    img.rgb.len()
                ));
            }
        }
    }
    if reference.width != test.width || reference.height != test.height {
        return Err(format!(
            "size mismatch: reference is {}×{}, test is {}×{}",
            reference.width, reference.height, test.width, test.height
        ));
    }
    if reference.is_empty() {
        return Err("the images have no pixels".to_string());
    }
    Ok(())
}

/// Sum over pixels of `f(reference pixel, test pixel)` on f64 values, after
/// [`check_same_size`]: the reduction under the pixel-wise metrics, in f64
/// so that large images do not lose the small errors of converged renders.
pub(super) fn pixel_sum(
    reference: &Image,
    test: &Image,
    f: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> Result<f64, String> {
    check_same_size(reference, test)?;
    Ok(reference
        .rgb
        .iter()
        .zip(&test.rgb)
        .map(|(r, t)| f(r.map(f64::from), t.map(f64::from)))
        .sum())
}

/// Mean over pixels of `f(reference pixel, test pixel)`.
pub(super) fn pixel_mean(
    reference: &Image,
    test: &Image,
    f: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> Result<f64, String> {
    Ok(pixel_sum(reference, test, f)? / reference.len() as f64)
}

/// Mean over pixels and channels of `f(reference value, test value)`.
pub(super) fn channel_mean(
    reference: &Image,
    test: &Image,
    f: impl Fn(f64, f64) -> f64,
) -> Result<f64, String> {
    let sum = pixel_sum(reference, test, |r, t| {
        (0..3).map(|c| f(r[c], t[c])).sum::<f64>()
    })?;
    Ok(sum / (3 * reference.len()) as f64)
}

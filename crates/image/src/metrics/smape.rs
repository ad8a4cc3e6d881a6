//! Symmetric mean absolute percentage error, as Peters 2025 reports it.

use super::pixels::pixel_mean;
use crate::image_io::Image;

/// ε added to the mean linear RGB value in the denominator of [`smape`].
pub const SMAPE_EPSILON: f64 = 0.01;

/// SMAPE of Peters 2025 (Fig. 12 caption: "symmetric mean absolute percentage
/// error (SMAPE) with ε := 0.01 added to the mean linear RGB value in the
/// denominator").
///
/// Our reading, per pixel p with linear channels t_c (test) and r_c
/// (reference):
///
/// ```text
/// e_p = mean_c |t_c − r_c|  /  ( (mean_c |t_c| + mean_c |r_c|) / 2 + ε )
/// SMAPE = mean_p e_p,    ε = 0.01
/// ```
///
/// The denominator is the pixel's mean linear RGB value (averaged over test
/// and reference, the "symmetric" part) plus ε, as the caption says; the
/// numerator is the mean absolute channel difference, so colour errors that
/// cancel in the RGB mean still count. For grey images (transmittance) this
/// equals the scalar |t − r| / ((|t| + |r|)/2 + ε). The result is a
/// fraction (0.05 = 5 %), bounded by 2.
pub fn smape(reference: &Image, test: &Image) -> Result<f64, String> {
    pixel_mean(reference, test, |r, t| {
        let mut num = 0.0;
        let mut den = 0.0;
        for c in 0..3 {
            num += (t[c] - r[c]).abs();
            den += t[c].abs() + r[c].abs();
        }
        (num / 3.0) / (den / 6.0 + SMAPE_EPSILON)
    })
}

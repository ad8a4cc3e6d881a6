//! Relative mean squared error.

use super::pixels::channel_mean;
use crate::image_io::Image;

/// ε in the denominator of [`relmse`], in linear units (1 % of white).
pub const RELMSE_EPSILON: f64 = 0.01;

/// relMSE = mean over pixels p and channels c of
/// (test − ref)² / (ref² + ε), ε = [`RELMSE_EPSILON`] = 0.01.
///
/// Dividing by the reference's square weighs errors in dark regions like
/// errors in bright ones, which matches how they are seen; ε keeps black
/// reference pixels from dominating. ε is added to ref², not to ref (the
/// form used by e.g. Rousselle et al. 2011 and most denoising papers).
pub fn relmse(reference: &Image, test: &Image) -> Result<f64, String> {
    channel_mean(reference, test, |r, t| {
        (t - r) * (t - r) / (r * r + RELMSE_EPSILON)
    })
}

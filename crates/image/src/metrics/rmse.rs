//! Root-mean-square error.

use super::pixels::channel_mean;
use crate::image_io::Image;

/// RMSE = sqrt(mean over pixels p and channels c of (test − ref)²), on
/// linear values.
///
/// The plain error whose square is bias² + variance, so it is the quantity
/// equal-time convergence plots compare across estimators. Accumulated in
/// f64 so that large images do not lose the small errors of converged
/// renders.
pub fn rmse(reference: &Image, test: &Image) -> Result<f64, String> {
    Ok(channel_mean(reference, test, |r, t| (t - r) * (t - r))?.sqrt())
}

//! Root-mean-square error.

use super::{check_same_size, Image};

/// RMSE = sqrt(mean over pixels p and channels c of (test − ref)²), on
/// linear values.
///
/// The plain error whose square is bias² + variance, so it is the quantity
/// equal-time convergence plots compare across estimators. Accumulated in
/// f64 so that large images do not lose the small errors of converged
/// renders.
pub fn rmse(reference: &Image, test: &Image) -> Result<f64, String> {
    check_same_size(reference, test)?;
    let sum: f64 = reference
        .rgb
        .iter()
        .zip(&test.rgb)
        .map(|(r, t)| {
            (0..3)
                .map(|c| {
                    let d = t[c] as f64 - r[c] as f64;
                    d * d
                })
                .sum::<f64>()
        })
        .sum();
    Ok((sum / (3 * reference.len()) as f64).sqrt())
}

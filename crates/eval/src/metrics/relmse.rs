//! Relative mean squared error.

use super::{check_same_size, Image};

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
    check_same_size(reference, test)?;
    let sum: f64 = reference
        .rgb
        .iter()
        .zip(&test.rgb)
        .map(|(r, t)| {
            (0..3)
                .map(|c| {
                    let (r, t) = (r[c] as f64, t[c] as f64);
                    (t - r) * (t - r) / (r * r + RELMSE_EPSILON)
                })
                .sum::<f64>()
        })
        .sum();
    Ok(sum / (3 * reference.len()) as f64)
}

//! Per-pixel z-test: is the difference between a test render and a
//! reference explained by their Monte Carlo noise?

use super::normal::normal_quantile;
use super::pixels::check_same_size;
use crate::image_io::Image;
use serde::Serialize;

/// Relative f32 rounding (in units of f32's ε) the test allows for: two
/// equal exact values stored by renderers that accumulate in f32 differ by
/// a few ULPs, and `restir`'s sky pixels (F·W of a background sample whose
/// W is a ratio of f32 sums) by up to 5.3·ε from the environment's exact
/// radiance (measured over 1024 sequences); 8·ε ≈ 10⁻⁶ relative.
pub const ROUNDING_ULPS: f64 = 8.0;

/// Default family-wise significance level of [`ztest`].
pub const ZTEST_ALPHA: f64 = 0.01;

/// Outcome of [`ztest`].
#[derive(Clone, Debug, Serialize)]
pub struct ZTest {
    /// Family-wise significance level α.
    pub alpha: f64,
    /// Number of pixel-channel tests: channels whose combined variance
    /// var_ref + var_test is positive.
    pub tests: usize,
    /// Šidák per-test level α_each = 1 − (1 − α)^(1/tests).
    pub alpha_each: f64,
    /// Two-sided |z| threshold Φ⁻¹(1 − α_each/2); ∞ when there is no test.
    pub threshold: f64,
    /// Largest |z| over all tests (0 when there is none).
    pub max_abs_z: f64,
    /// Pixel (x, y) where `max_abs_z` occurs.
    pub max_abs_z_pixel: Option<(usize, usize)>,
    /// Pixels with at least one failing channel (statistical or exact).
    pub failing_pixels: usize,
    /// `failing_pixels` / number of pixels.
    pub failing_fraction: f64,
    /// Pixels with a channel whose combined variance is 0 (both images
    /// exact there); such a channel passes only if the values are equal.
    pub zero_variance_pixels: usize,
    /// Pixels failing because a zero-variance channel differs (included in
    /// `failing_pixels`).
    pub zero_variance_mismatches: usize,
    /// Expected number of failing tests if the test image is unbiased and
    /// the errors normal: tests · α_each ≈ −ln(1 − α) (0.01005 for α = 0.01),
    /// far below one.
    pub expected_failures_h0: f64,
    /// Mean z per channel over that channel's tests. Under H0 it is about
    /// N(0, 1/tests_c); a small uniform bias that no single pixel reveals
    /// shows up here (diagnostic only, not part of the verdict).
    pub mean_z: [f64; 3],
    /// The verdict: true iff no pixel fails.
    pub pass: bool,
    /// Per-pixel max |z| over the channels (∞ for an exact mismatch, 0 for
    /// exact equality), for visualising where the images disagree.
    #[serde(skip)]
    pub map: Vec<f32>,
}

/// Same size, α in (0, 1), and a variance layer in at least one image.
fn check_inputs(reference: &Image, test: &Image, alpha: f64) -> Result<(), String> {
    check_same_size(reference, test)?;
    if !(alpha > 0.0 && alpha < 1.0) {
        return Err(format!("alpha must be in (0, 1), got {alpha}"));
    }
    if reference.variance.is_none() && test.variance.is_none() {
        return Err(
            "the z-test needs a variance layer (variance.R/G/B) in the reference or \
             the test; fogbank writes one when spp > 1"
                .to_string(),
        );
    }
    Ok(())
}

/// The z of every pixel channel, its kind (0: exact and equal, 1: a
/// statistical test, 2: an exact mismatch, negative or NaN variance, or
/// NaN values) and the number of statistical tests.
fn channel_tests(reference: &Image, test: &Image) -> (Vec<[f64; 3]>, Vec<[u8; 3]>, usize) {
    let zero = [0f32; 3];
    let var_at = |img: &Image, i: usize| img.variance.as_ref().map_or(zero, |v| v[i]);

    let n_pix = reference.len();
    let mut z = vec![[0f64; 3]; n_pix];
    // Per channel: 0 = exact and equal, 1 = statistical test, 2 = exact mismatch.
    let mut kind = vec![[0u8; 3]; n_pix];
    let mut tests = 0usize;
    for i in 0..n_pix {
        let (r, t) = (reference.rgb[i], test.rgb[i]);
        let (vr, vt) = (var_at(reference, i), var_at(test, i));
        for c in 0..3 {
            let var = vr[c] as f64 + vt[c] as f64;
            let d = t[c] as f64 - r[c] as f64;
            // f32 storage rounds each value by up to half an ULP, and a
            // renderer that accumulates and normalises in f32 (Mitsuba:
            // Σ w·L / Σ w) by a few more; the variance layers do not include
            // that, so add ROUNDING_ULPS of it as noise.
            let rounding =
                ROUNDING_ULPS * f32::EPSILON as f64 * (t[c].abs().max(r[c].abs()) as f64);
            if var > 0.0 {
                z[i][c] = d / (var + rounding * rounding).sqrt();
                kind[i][c] = 1;
                tests += 1;
            } else if var == 0.0 && d.abs() <= rounding {
                kind[i][c] = 0;
            } else {
                // Unequal exact values, negative or NaN variance, NaN values.
                z[i][c] = f64::INFINITY;
                kind[i][c] = 2;
            }
        }
    }

    (z, kind, tests)
}

/// The Šidák-corrected level α_each = 1 − (1 − α)^(1/n) of each of `tests`
/// tests and its two-sided threshold on |z|.
fn sidak_threshold(alpha: f64, tests: usize) -> (f64, f64) {
    if tests == 0 {
        (0.0, f64::INFINITY)
    } else {
        // 1 − (1 − α)^(1/n) without cancellation for large n.
        let a = -((-alpha).ln_1p() / tests as f64).exp_m1();
        (a, -normal_quantile(0.5 * a))
    }
}

/// [`ztest_with`] at the family-wise level α = [`ZTEST_ALPHA`] = 0.01.
pub fn ztest(reference: &Image, test: &Image) -> Result<ZTest, String> {
    ztest_with(reference, test, ZTEST_ALPHA)
}

/// Per-pixel, per-channel z-test of `test` against `reference`:
///
/// ```text
/// z = (test − ref) / sqrt(var_ref + var_test)
/// ```
///
/// with the variances of the mean from the images' `variance` layers (the
/// test's counts only if present; at least one image must have one). A
/// pixel fails if any channel has |z| > z*, the two-sided threshold for the
/// Šidák-corrected level α_each = 1 − (1 − α)^(1/n) over all n pixel-channel
/// tests, so that an unbiased test image with normal errors fails anywhere
/// with probability ≤ α. Channels where both variances are 0 are exact:
/// they pass when the values are equal and fail otherwise (counted apart in
/// `zero_variance_mismatches`); non-finite z (NaN input) fails.
///
/// "Equal" and the variance allow for f32 rounding: the denominator adds
/// (k·ε_f32·max(|test|, |ref|))² with k = [`ROUNDING_ULPS`], and exact
/// values within that distance are equal. Without it, converged pixels (T = 1 with a variance of 1e-17 from
/// accumulation round-off) fail with |z| ≈ 8 over one ULP.
///
/// Verdict: pass iff no pixel fails. Under H0 the expected number of
/// failing tests is n·α_each ≈ −ln(1 − α) ≈ 0.01, far below one, so "no
/// more failures than expected under H0" and "no failure" are the same
/// rule.
///
/// Caveat: the variances are themselves estimates. At low spp a skewed
/// estimator (e.g. a 0/1 transmittance) can produce a pixel whose samples
/// all agree, hence variance 0, although its true variance is not; with a
/// low-variance reference such a pixel may fail although the estimator is
/// unbiased. Compare renders with enough samples for the CLT to apply.
pub fn ztest_with(reference: &Image, test: &Image, alpha: f64) -> Result<ZTest, String> {
    check_inputs(reference, test, alpha)?;
    let n_pix = reference.len();
    let (z, kind, tests) = channel_tests(reference, test);
    let (alpha_each, threshold) = sidak_threshold(alpha, tests);

    let mut failing_pixels = 0;
    let mut zero_variance_pixels = 0;
    let mut zero_variance_mismatches = 0;
    let mut max_abs_z = 0.0f64;
    let mut max_abs_z_pixel = None;
    let mut z_sum = [0f64; 3];
    let mut z_count = [0usize; 3];
    let mut map = vec![0f32; n_pix];
    for i in 0..n_pix {
        let mut fail = false;
        let mut exact_mismatch = false;
        let mut pixel_max = 0.0f64;
        if kind[i].iter().any(|&k| k != 1) {
            zero_variance_pixels += 1;
        }
        for c in 0..3 {
            match kind[i][c] {
                1 => {
                    let a = z[i][c].abs();
                    fail |= a.is_nan() || a > threshold;
                    pixel_max = pixel_max.max(a);
                    if a > max_abs_z {
                        max_abs_z = a;
                        max_abs_z_pixel = Some((i % reference.width, i / reference.width));
                    }
                    z_sum[c] += z[i][c];
                    z_count[c] += 1;
                }
                2 => {
                    fail = true;
                    exact_mismatch = true;
                    pixel_max = f64::INFINITY;
                }
                _ => {}
            }
        }
        if fail {
            failing_pixels += 1;
        }
        if exact_mismatch {
            zero_variance_mismatches += 1;
        }
        map[i] = pixel_max as f32;
    }
    let mean_z = [0, 1, 2].map(|c| {
        if z_count[c] > 0 {
            z_sum[c] / z_count[c] as f64
        } else {
            0.0
        }
    });
    Ok(ZTest {
        alpha,
        tests,
        alpha_each,
        threshold,
        max_abs_z,
        max_abs_z_pixel,
        failing_pixels,
        failing_fraction: failing_pixels as f64 / n_pix as f64,
        zero_variance_pixels,
        zero_variance_mismatches,
        expected_failures_h0: tests as f64 * alpha_each,
        mean_z,
        pass: failing_pixels == 0,
        map,
    })
}

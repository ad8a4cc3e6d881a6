//! Image comparison metrics: a test image against a reference.
//!
//! The first argument is always the reference. Every metric returns an
//! error instead of panicking when the images cannot be compared (different
//! sizes, a missing variance layer), because the callers are batch tools
//! (convergence plots, estimator comparisons) that report and continue.
//!
//! | metric | what it answers |
//! |---|---|
//! | [`rmse`] | absolute error, dominated by bright pixels |
//! | [`relmse`] | error relative to the reference's brightness |
//! | [`smape`] | seed 000's error measure (Fig. 12), bounded in [0, 2] |
//! | [`flip()`] | perceived difference (NVIDIA's FLIP, LDR and HDR) |
//! | [`ztest()`] | whether the difference is explained by Monte Carlo noise |

pub mod flip;
pub mod normal;
pub mod relmse;
pub mod rmse;
pub mod smape;
pub mod ztest;

pub use crate::image_io::{read_image, read_pair, Image};
pub use flip::{flip, flip_with, FlipMode, FlipOptions, FlipResult, Tonemapper};
pub use relmse::{relmse, RELMSE_EPSILON};
pub use rmse::rmse;
pub use smape::{smape, SMAPE_EPSILON};
pub use ztest::{ztest, ztest_with, ZTest, ZTEST_ALPHA};

/// The metrics by name, for command lines and reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Metric {
    Rmse,
    Relmse,
    Smape,
    Flip,
    Ztest,
}

impl Metric {
    /// Every metric, in the order reports list them.
    pub const ALL: [Metric; 5] = [
        Metric::Rmse,
        Metric::Relmse,
        Metric::Smape,
        Metric::Flip,
        Metric::Ztest,
    ];

    /// The name used on the command line and as JSON key.
    pub fn name(self) -> &'static str {
        match self {
            Metric::Rmse => "rmse",
            Metric::Relmse => "relmse",
            Metric::Smape => "smape",
            Metric::Flip => "flip",
            Metric::Ztest => "ztest",
        }
    }

    /// Parses one name (case-insensitive); `all` gives every metric.
    pub fn parse(name: &str) -> Result<Vec<Metric>, String> {
        let n = name.trim().to_ascii_lowercase();
        if n == "all" {
            return Ok(Metric::ALL.to_vec());
        }
        Metric::ALL
            .iter()
            .find(|m| m.name() == n)
            .map(|&m| vec![m])
            .ok_or_else(|| {
                format!(
                    "unknown metric {name:?}; expected one of rmse, relmse, smape, flip, ztest, all"
                )
            })
    }
}

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
fn pixel_sum(
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
fn pixel_mean(
    reference: &Image,
    test: &Image,
    f: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> Result<f64, String> {
    Ok(pixel_sum(reference, test, f)? / reference.len() as f64)
}

/// Mean over pixels and channels of `f(reference value, test value)`.
fn channel_mean(
    reference: &Image,
    test: &Image,
    f: impl Fn(f64, f64) -> f64,
) -> Result<f64, String> {
    let sum = pixel_sum(reference, test, |r, t| {
        (0..3).map(|c| f(r[c], t[c])).sum::<f64>()
    })?;
    Ok(sum / (3 * reference.len()) as f64)
}

//! `fogbank compare` as a library call: metrics of a test image against a
//! reference (rmse, relmse, smape, FLIP, the per-pixel z-test), each as a
//! number or a record, with the options the command takes.

use crate::error::Error;
use fogbank_image::metrics::{self, FlipMode, FlipOptions, FlipResult, Tonemapper, ZTest};
/// The images compared (a pair read and checked for size by [`read_pair`]),
/// the metrics, and the z-test's default significance level.
pub use fogbank_image::metrics::{read_pair, Image, Metric, ZTEST_ALPHA};
use serde_json::{json, Value};

/// FLIP's and the z-test's settings.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    pub flip: FlipOptions,
    /// The z-test's family-wise significance level.
    pub alpha: f64,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            flip: FlipOptions {
                ppd: metrics::flip::default_ppd(),
                ..FlipOptions::default()
            },
            alpha: metrics::ZTEST_ALPHA,
        }
    }
}

impl CompareOptions {
    /// FLIP's mode (`auto`, `ldr`, `hdr`), pixels per degree (default
    /// 67.02) and HDR tone mapper (`aces`, `hable`, `reinhard`), and the
    /// z-test's α.
    pub fn new(
        mode: &str,
        ppd: Option<f32>,
        tonemapper: &str,
        alpha: f64,
    ) -> Result<CompareOptions, Error> {
        let mode = match mode.to_ascii_lowercase().as_str() {
            "auto" => FlipMode::Auto,
            "ldr" => FlipMode::Ldr,
            "hdr" => FlipMode::Hdr,
            other => {
                return Err(Error::invalid(format!(
                    "--flip-mode: expected auto, ldr or hdr, got {other:?}"
                )))
            }
        };
        let tonemapper = match tonemapper.to_ascii_lowercase().as_str() {
            "aces" => Tonemapper::Aces,
            "hable" => Tonemapper::Hable,
            "reinhard" => Tonemapper::Reinhard,
            other => {
                return Err(Error::invalid(format!(
                    "--tonemapper: expected aces, hable or reinhard, got {other:?}"
                )))
            }
        };
        if !(alpha > 0.0 && alpha < 1.0) {
            return Err(Error::invalid(format!("--alpha: {alpha} is not in (0, 1)")));
        }
        Ok(CompareOptions {
            flip: FlipOptions {
                mode,
                ppd: ppd.unwrap_or_else(metrics::flip::default_ppd),
                tonemapper,
                ..FlipOptions::default()
            },
            alpha,
        })
    }
}

/// A metric's result.
#[derive(Clone, Debug)]
pub enum Outcome {
    Scalar(f64),
    Flip(FlipResult),
    Ztest(ZTest),
    /// Not computed, and why.
    Skipped(&'static str),
}

impl Outcome {
    /// As `fogbank compare --json` prints it.
    pub fn to_json(&self) -> Value {
        match self {
            Outcome::Scalar(v) => json!(v),
            Outcome::Flip(f) => serde_json::to_value(f).unwrap_or(Value::Null),
            Outcome::Ztest(z) => serde_json::to_value(z).unwrap_or(Value::Null),
            Outcome::Skipped(why) => json!({ "skipped": why }),
        }
    }
}

/// The metrics named in `names` (each a name, `all`, or a comma-separated
/// list), each once, and whether the z-test was asked for by name (`all`
/// skips it when neither image has a variance layer).
pub fn parse_metrics(names: &[String]) -> Result<(Vec<Metric>, bool), Error> {
    let mut wanted: Vec<Metric> = Vec::new();
    let mut explicit_ztest = false;
    for name in names.iter().flat_map(|n| n.split(',')) {
        for m in Metric::parse(name).map_err(Error::invalid)? {
            explicit_ztest |= m == Metric::Ztest && !name.trim().eq_ignore_ascii_case("all");
            if !wanted.contains(&m) {
                wanted.push(m);
            }
        }
    }
    Ok((wanted, explicit_ztest))
}

/// Each of `wanted` of `test` against `reference` (same size).
pub fn compare(
    reference: &Image,
    test: &Image,
    wanted: &[Metric],
    explicit_ztest: bool,
    opts: &CompareOptions,
) -> Result<Vec<(Metric, Outcome)>, Error> {
    metrics::check_same_size(reference, test).map_err(Error::invalid)?;
    let has_variance = reference.variance.is_some() || test.variance.is_some();
    let mut results = Vec::new();
    for &m in wanted {
        let outcome = match m {
            Metric::Rmse => {
                Outcome::Scalar(metrics::rmse(reference, test).map_err(Error::invalid)?)
            }
            Metric::Relmse => {
                Outcome::Scalar(metrics::relmse(reference, test).map_err(Error::invalid)?)
            }
            Metric::Smape => {
                Outcome::Scalar(metrics::smape(reference, test).map_err(Error::invalid)?)
            }
            Metric::Flip => Outcome::Flip(
                metrics::flip_with(reference, test, &opts.flip).map_err(Error::invalid)?,
            ),
            Metric::Ztest if !has_variance && !explicit_ztest => Outcome::Skipped(
                "neither image has a variance layer (fogbank writes one when spp > 1)",
            ),
            Metric::Ztest => Outcome::Ztest(
                metrics::ztest_with(reference, test, opts.alpha).map_err(Error::invalid)?,
            ),
        };
        results.push((m, outcome));
    }
    Ok(results)
}

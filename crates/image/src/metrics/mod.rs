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
//! | [`smape`] | Peters 2025's error measure (Fig. 12), bounded in [0, 2] |
//! | [`flip()`] | perceived difference (NVIDIA's FLIP, LDR and HDR) |
//! | [`ztest()`] | whether the difference is explained by Monte Carlo noise |

pub mod flip;
mod flip_colour;
pub mod normal;
mod pixels;
pub mod relmse;
pub mod rmse;
pub mod smape;
pub mod ztest;

pub use crate::image_io::{read_image, read_pair, Image};
pub use flip::{flip, flip_with, FlipMode, FlipOptions, FlipResult, Tonemapper};
pub use pixels::check_same_size;
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

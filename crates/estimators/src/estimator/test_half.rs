//! `test_half`: a test-only estimator (registered under `#[cfg(test)]`)
//! that returns a constant transmittance, to check that one file and one
//! registry line are all an estimator needs.

use super::options::{OptionValue, Options};
use super::plugin::EstimatorPlugin;
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TestHalf {
    /// The transmittance it returns on every ray that meets the medium.
    pub level: f32,
}

impl EstimatorPlugin for TestHalf {
    const NAME: &'static str = "test_half";
    const BIASED: bool = true;
    const DESCRIPTION: &'static str = "a constant transmittance (tests only)";
    const KEYS: &'static [&'static str] = &["level"];
    const OPTIONS_HELP: &'static str = "level=0.5";

    fn read(o: &Options) -> Result<Self, String> {
        Ok(TestHalf {
            level: o.number("level")?.unwrap_or(0.5),
        })
    }

    fn options(&self) -> Options {
        Options::default().with("level", OptionValue::Float(self.level as f64))
    }

    fn transmittance(&self, _: MediumView<'_>, _: &RaySegment, _: &mut Pcg32) -> Estimate {
        Estimate {
            transmittance: self.level,
            lookups: 0,
        }
    }
}

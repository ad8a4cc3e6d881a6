//! `jackknife_naive`: exp(−X) from one optical-depth estimate of 2N
//! samples, by the jackknife's own machinery (`crate::jackknife`; Peters
//! 2025 Fig. 8c).

use super::options::Options;
use super::plugin::{read_samples_and_jitter, samples_and_jitter, EstimatorPlugin};
use crate::jackknife;
use crate::optical_depth::Jitter;
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JackknifeNaive {
    pub samples: u32,
    pub jitter: Jitter,
}

impl EstimatorPlugin for JackknifeNaive {
    const NAME: &'static str = "jackknife_naive";
    const BIASED: bool = true;
    const DESCRIPTION: &'static str =
        "exp(−X) from one estimate of 2N samples, same machinery (Fig. 8c)";
    const KEYS: &'static [&'static str] = &["samples", "jitter"];
    const OPTIONS_HELP: &'static str = "samples=10, jitter=stratified|uniform";

    fn read(o: &Options) -> Result<Self, String> {
        let (samples, jitter) = read_samples_and_jitter(o)?;
        Ok(JackknifeNaive { samples, jitter })
    }

    fn options(&self) -> Options {
        samples_and_jitter(self.samples, self.jitter)
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let (samples, jitter) = (self.samples, self.jitter);
        with_view!(view, v => jackknife::naive_transmittance(&v, seg, samples, jitter, rng))
    }
}

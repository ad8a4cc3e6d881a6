//! `jackknife_mean_importance`: the jackknife with mean importance and no
//! control variate (`crate::jackknife`; Peters 2025 Fig. 9's ablation).

use super::options::Options;
use super::plugin::{read_samples_and_jitter, samples_and_jitter, EstimatorPlugin};
use crate::jackknife;
use crate::optical_depth::{Importance, Jitter};
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JackknifeMeanImportance {
    pub samples: u32,
    pub jitter: Jitter,
}

impl EstimatorPlugin for JackknifeMeanImportance {
    const NAME: &'static str = "jackknife_mean_importance";
    const BIASED: bool = true;
    const DESCRIPTION: &'static str =
        "jackknife with mean importance and no control variate (Fig. 9 ablation)";
    const KEYS: &'static [&'static str] = &["samples", "jitter"];
    const OPTIONS_HELP: &'static str = "samples=10, jitter=stratified|uniform";

    fn read(o: &Options) -> Result<Self, String> {
        let (samples, jitter) = read_samples_and_jitter(o)?;
        Ok(JackknifeMeanImportance { samples, jitter })
    }

    fn options(&self) -> Options {
        samples_and_jitter(self.samples, self.jitter)
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let sampling = jackknife::Sampling {
            importance: Importance::Mean,
            ..jackknife::Sampling::fixed_count(self.samples, self.jitter)
        };
        with_view!(view, v => jackknife::transmittance(&v, seg, sampling, rng))
    }
}

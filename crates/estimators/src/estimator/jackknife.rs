//! `jackknife`: Peters 2025's jackknife transmittance, cos(S)·exp(−X̄) from
//! two interleaved optical-depth estimates (`crate::jackknife`; Algs. 1
//! and 2, Eqs. 4 and 5), with a fixed sample count or a fixed step in
//! optical depth.

use super::options::{OptionValue, Options};
use super::plugin::{jitter_value, read_jitter, read_samples, EstimatorPlugin};
use crate::jackknife::{self, StepMode};
use crate::optical_depth::Jitter;
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jackknife {
    pub samples: u32,
    pub mode: StepMode,
    pub jitter: Jitter,
}

impl EstimatorPlugin for Jackknife {
    const NAME: &'static str = "jackknife";
    const BIASED: bool = true;
    const DESCRIPTION: &'static str =
        "Peters 2025: cos(S)·exp(−X̄) from two interleaved estimates (Alg. 1, 2; Eq. 4, 5)";
    const KEYS: &'static [&'static str] = &["samples", "mode", "step", "jitter"];
    const OPTIONS_HELP: &'static str =
        "samples=10, mode=fixed_count|fixed_step, step=1.0, jitter=stratified|uniform";

    fn read(o: &Options) -> Result<Self, String> {
        Ok(Jackknife {
            samples: read_samples(o)?,
            mode: read_mode(o)?,
            jitter: read_jitter(o)?,
        })
    }

    fn options(&self) -> Options {
        let o = Options::default().with("samples", OptionValue::Int(self.samples.into()));
        let o = match self.mode {
            StepMode::FixedCount => o.with("mode", OptionValue::Text("fixed_count".into())),
            StepMode::FixedStep(s) => o
                .with("mode", OptionValue::Text("fixed_step".into()))
                .with("step", OptionValue::Float(s as f64)),
        };
        o.with("jitter", jitter_value(self.jitter))
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let sampling = jackknife::Sampling {
            mode: self.mode,
            ..jackknife::Sampling::fixed_count(self.samples, self.jitter)
        };
        with_view!(view, v => jackknife::transmittance(&v, seg, sampling, rng))
    }
}

/// The step mode: a fixed sample count, or a fixed step in optical depth
/// (`step`, default 1).
fn read_mode(o: &Options) -> Result<StepMode, String> {
    match o.text("mode")? {
        None | Some("fixed_count") => {
            if o.get("step").is_some() {
                return Err("step: only used with mode = \"fixed_step\"".into());
            }
            Ok(StepMode::FixedCount)
        }
        Some("fixed_step") => {
            let s = o.number("step")?.unwrap_or(1.0);
            if !(s > 0.0 && s.is_finite()) {
                return Err(format!("step: {s} must be a positive optical depth"));
            }
            Ok(StepMode::FixedStep(s))
        }
        Some(m) => Err(format!("mode: `{m}` is not fixed_count or fixed_step")),
    }
}

//! What an estimator is to the registry: a parameter struct that knows its
//! name, what it computes, the options it takes and how to read and write
//! them, and its transmittance along a ray in each storage type. One file
//! per estimator beside this one implements it, over the algorithm in the
//! crate's own module (`crate::ratio_tracking`, `crate::jackknife`, …).

use super::options::{OptionValue, Options};
use crate::optical_depth::Jitter;
use crate::roulette::DEFAULT_ROULETTE;
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{AnalyticView, MediumView};

pub trait EstimatorPlugin: Sized + Copy {
    /// The name scenes, the command line and Python use.
    const NAME: &'static str;
    const BIASED: bool;
    /// What it computes, with the paper and equation.
    const DESCRIPTION: &'static str;
    /// The option keys it takes, in the order listings show them.
    const KEYS: &'static [&'static str];
    /// Its options and their defaults, for `fogbank estimators`.
    const OPTIONS_HELP: &'static str;

    /// The estimator with `o` applied (`o` holds only keys of [`Self::KEYS`]);
    /// a bad value is an error naming its key.
    fn read(o: &Options) -> Result<Self, String>;

    /// Every option it takes, spelled out: [`Self::read`] gives it back.
    fn options(&self) -> Options;

    /// Transmittance along `seg` (index space, already clipped to the
    /// medium) of the medium `view` shows.
    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate;
}

/// `samples`: a fixed sample count in 1..=2²⁰ (default 10).
pub fn read_samples(o: &Options) -> Result<u32, String> {
    let samples = o.count("samples")?.unwrap_or(10);
    if samples == 0 || samples > 1 << 20 {
        return Err(format!("samples: {samples} is outside 1..=1048576"));
    }
    Ok(samples)
}

/// `roulette`: a threshold weight in [0, 1) (0: off; default
/// [`DEFAULT_ROULETTE`]).
pub fn read_roulette(o: &Options) -> Result<f32, String> {
    let r = o.number("roulette")?.unwrap_or(DEFAULT_ROULETTE);
    if !(0.0..1.0).contains(&r) {
        return Err(format!("roulette: {r} is outside [0, 1)"));
    }
    Ok(r)
}

/// [`read_roulette`]'s option written back.
pub fn roulette_option(roulette: f32) -> Options {
    Options::default().with("roulette", OptionValue::Float(roulette as f64))
}

/// `jitter`: stratified (default) or uniform.
pub fn read_jitter(o: &Options) -> Result<Jitter, String> {
    match o.text("jitter")? {
        None | Some("stratified") => Ok(Jitter::Stratified),
        Some("uniform") => Ok(Jitter::Uniform),
        Some(j) => Err(format!("jitter: `{j}` is not stratified or uniform")),
    }
}

/// `samples` and `jitter`, the options of the jackknife's ablations.
pub fn read_samples_and_jitter(o: &Options) -> Result<(u32, Jitter), String> {
    Ok((read_samples(o)?, read_jitter(o)?))
}

/// [`read_samples_and_jitter`]'s options written back.
pub fn samples_and_jitter(samples: u32, jitter: Jitter) -> Options {
    Options::default()
        .with("samples", OptionValue::Int(samples.into()))
        .with("jitter", jitter_value(jitter))
}

pub fn jitter_value(j: Jitter) -> OptionValue {
    OptionValue::Text(
        match j {
            Jitter::Stratified => "stratified",
            Jitter::Uniform => "uniform",
        }
        .into(),
    )
}

/// The exact optical depth of an analytic medium along `seg`, no lookups.
pub fn analytic_optical_depth(a: &AnalyticView<'_>, seg: &RaySegment) -> (f64, u32) {
    let tau = a.field.optical_depth(&seg.ray, seg.t0, seg.t1) * a.scale as f64;
    (tau, 0)
}

/// The estimate exp(−τ) of an exact optical depth τ, with its lookups.
pub fn exact((tau, lookups): (f64, u32)) -> Estimate {
    Estimate {
        transmittance: (-tau).exp() as f32,
        lookups,
    }
}

//! `unbiased_ray_marching`: Kettunen et al. 2021's unbiased estimator, a
//! power series with Russian roulette and U-statistics (`crate::kettunen`).

use super::options::{OptionValue, Options};
use super::plugin::EstimatorPlugin;
use crate::{kettunen, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnbiasedRayMarching {
    /// Multiplier of the samples per estimate (mult · N_CMF / 1.31945), 1..=16.
    pub mult: u32,
}

impl EstimatorPlugin for UnbiasedRayMarching {
    const NAME: &'static str = "unbiased_ray_marching";
    const BIASED: bool = false;
    const DESCRIPTION: &'static str =
        "Kettunen et al. 2021: power series, Russian roulette, U-statistics";
    const KEYS: &'static [&'static str] = &["mult"];
    const OPTIONS_HELP: &'static str = "mult=1";

    fn read(o: &Options) -> Result<Self, String> {
        let mult = o.count("mult")?.unwrap_or(1);
        if !(1..=16).contains(&mult) {
            return Err(format!("mult: {mult} is outside 1..=16"));
        }
        Ok(UnbiasedRayMarching { mult })
    }

    fn options(&self) -> Options {
        Options::default().with("mult", OptionValue::Int(self.mult.into()))
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let mult = self.mult;
        with_view!(view, v => kettunen::unbiased_transmittance(&v, seg, mult, rng))
    }
}

//! `biased_ray_marching`: Kettunen et al. 2021's biased estimator, exp(−X)
//! with mean importance and N_CMF samples (`crate::kettunen`).

use super::options::{OptionValue, Options};
use super::plugin::EstimatorPlugin;
use crate::{kettunen, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BiasedRayMarching {
    /// Twice the N_CMF samples.
    pub doubled: bool,
}

impl EstimatorPlugin for BiasedRayMarching {
    const NAME: &'static str = "biased_ray_marching";
    const BIASED: bool = true;
    const DESCRIPTION: &'static str =
        "Kettunen et al. 2021: exp(−X), mean importance, N_CMF samples";
    const KEYS: &'static [&'static str] = &["doubled"];
    const OPTIONS_HELP: &'static str = "doubled=false";

    fn read(o: &Options) -> Result<Self, String> {
        Ok(BiasedRayMarching {
            doubled: o.flag("doubled")?.unwrap_or(false),
        })
    }

    fn options(&self) -> Options {
        Options::default().with("doubled", OptionValue::Bool(self.doubled))
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let doubled = self.doubled;
        with_view!(view, v => kettunen::biased_transmittance(&v, seg, doubled, rng))
    }
}

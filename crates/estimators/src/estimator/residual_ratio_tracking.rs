//! `residual_ratio_tracking`: ratio tracking of the residual over a
//! per-super-voxel control extinction (`crate::residual_ratio_tracking`;
//! Novák et al. 2014), Russian roulette below a weight.

use super::options::Options;
use super::plugin::{read_roulette, roulette_option, EstimatorPlugin};
use crate::{residual_ratio_tracking, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResidualRatioTracking {
    /// The weight below which the walk plays Russian roulette (0: never).
    pub roulette: f32,
}

impl EstimatorPlugin for ResidualRatioTracking {
    const NAME: &'static str = "residual_ratio_tracking";
    const BIASED: bool = false;
    const DESCRIPTION: &'static str =
        "ratio tracking of the residual over a per-super-voxel control (Novák et al. 2014)";
    const KEYS: &'static [&'static str] = &["roulette"];
    const OPTIONS_HELP: &'static str =
        "roulette=0.03 (Russian roulette below this weight; 0: off)";

    fn read(o: &Options) -> Result<Self, String> {
        Ok(ResidualRatioTracking {
            roulette: read_roulette(o)?,
        })
    }

    fn options(&self) -> Options {
        roulette_option(self.roulette)
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let roulette = self.roulette;
        with_view!(view, v => Estimate::of_one_channel(
            residual_ratio_tracking::transmittance_scaled(&v, seg, rng, [1.0], roulette)
        ))
    }
}

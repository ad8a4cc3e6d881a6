//! `ratio_tracking`: ratio tracking with super-voxel majorants
//! (`crate::ratio_tracking`; Novák et al. 2014), Russian roulette below a
//! weight (`crate::roulette`).

use super::options::Options;
use super::plugin::{read_roulette, roulette_option, EstimatorPlugin};
use crate::{ratio_tracking, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RatioTracking {
    /// The weight below which the walk plays Russian roulette (0: never).
    pub roulette: f32,
}

impl EstimatorPlugin for RatioTracking {
    const NAME: &'static str = "ratio_tracking";
    const BIASED: bool = false;
    const DESCRIPTION: &'static str =
        "ratio tracking with super-voxel majorants (Novák et al. 2014)";
    const KEYS: &'static [&'static str] = &["roulette"];
    const OPTIONS_HELP: &'static str =
        "roulette=0.03 (Russian roulette below this weight; 0: off)";

    fn read(o: &Options) -> Result<Self, String> {
        Ok(RatioTracking {
            roulette: read_roulette(o)?,
        })
    }

    fn options(&self) -> Options {
        roulette_option(self.roulette)
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        let roulette = self.roulette;
        with_view!(view, v => ratio_tracking::transmittance(&v, seg, rng, roulette))
    }
}

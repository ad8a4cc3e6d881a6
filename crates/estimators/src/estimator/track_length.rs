//! `track_length`: delta tracking's 0/1 estimate with super-voxel
//! majorants (`crate::track_length`; Peters 2025 §2.2).

use super::options::Options;
use super::plugin::EstimatorPlugin;
use crate::{track_length, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrackLength;

impl EstimatorPlugin for TrackLength {
    const NAME: &'static str = "track_length";
    const BIASED: bool = false;
    const DESCRIPTION: &'static str = "delta tracking with super-voxel majorants, returns 0 or 1";
    const KEYS: &'static [&'static str] = &[];
    const OPTIONS_HELP: &'static str = "";

    fn read(_: &Options) -> Result<Self, String> {
        Ok(TrackLength)
    }

    fn options(&self) -> Options {
        Options::default()
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
        with_view!(view, v => track_length::transmittance(&v, seg, rng))
    }
}

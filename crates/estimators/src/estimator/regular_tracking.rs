//! `regular_tracking`: the exact optical depth of the nearest-filtered grid
//! by voxel DDA (`crate::regular_tracking`); analytic media integrate their
//! field exactly.

use super::options::Options;
use super::plugin::{analytic_optical_depth, exact, EstimatorPlugin};
use crate::{regular_tracking, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RegularTracking;

impl EstimatorPlugin for RegularTracking {
    const NAME: &'static str = "regular_tracking";
    const BIASED: bool = false;
    const DESCRIPTION: &'static str =
        "exact optical depth of the nearest-filtered grid by voxel DDA";
    const KEYS: &'static [&'static str] = &[];
    const OPTIONS_HELP: &'static str = "";

    fn read(_: &Options) -> Result<Self, String> {
        Ok(RegularTracking)
    }

    fn options(&self) -> Options {
        Options::default()
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, _: &mut Pcg32) -> Estimate {
        exact(match view {
            MediumView::F16(v) => regular_tracking::optical_depth(&v, seg),
            MediumView::F32(v) => regular_tracking::optical_depth(&v, seg),
            MediumView::Analytic(a) => analytic_optical_depth(&a, seg),
        })
    }
}

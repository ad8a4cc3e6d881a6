//! `analytic_trilinear`: the exact optical depth of the trilinear
//! interpolant, a cubic per voxel (`crate::analytic_trilinear`; Lin et al.
//! 2021 §5); analytic media integrate their field exactly.

use super::options::Options;
use super::plugin::{analytic_optical_depth, exact, EstimatorPlugin};
use crate::{analytic_trilinear, Estimate};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::MediumView;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AnalyticTrilinear;

impl EstimatorPlugin for AnalyticTrilinear {
    const NAME: &'static str = "analytic_trilinear";
    const BIASED: bool = false;
    const DESCRIPTION: &'static str =
        "exact optical depth of the trilinear interpolant (cubic per voxel)";
    const KEYS: &'static [&'static str] = &[];
    const OPTIONS_HELP: &'static str = "";

    fn read(_: &Options) -> Result<Self, String> {
        Ok(AnalyticTrilinear)
    }

    fn options(&self) -> Options {
        Options::default()
    }

    fn transmittance(&self, view: MediumView<'_>, seg: &RaySegment, _: &mut Pcg32) -> Estimate {
        exact(match view {
            MediumView::F16(v) => analytic_trilinear::optical_depth(&v, seg),
            MediumView::F32(v) => analytic_trilinear::optical_depth(&v, seg),
            MediumView::Analytic(a) => analytic_optical_depth(&a, seg),
        })
    }
}

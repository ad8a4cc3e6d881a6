//! The drawing area every panel draws on, the chart that axes set up in
//! it, and plotters' errors as this module reports them.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

pub(super) type Area<DB> = DrawingArea<DB, plotters::coord::Shift>;
pub(super) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

pub(super) fn err(e: impl std::fmt::Display) -> String {
    format!("plot: {e}")
}

//! Line plots (linear or log axes).

use plotters::prelude::*;

use super::area::Area;
use super::axes::{auto_range, axes, draw_series, legend_and_notes, AxesLayout};
use super::style::{Axis, Corner, Series};
use super::text::Ink;

#[derive(Clone, Debug, Default)]
pub struct LinePlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_axis: Axis,
    pub y_axis: Axis,
    /// Explicit ranges (data units); automatic from the data when `None`.
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub series: Vec<Series>,
    pub legend: Corner,
    /// Free text in the top-left corner of the plotting area, one line per
    /// entry.
    pub notes: Vec<String>,
}

impl LinePlot {
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        LinePlot {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Default::default()
        }
    }
    pub fn log_x(mut self) -> Self {
        self.x_axis = Axis::Log;
        self
    }
    pub fn log_y(mut self) -> Self {
        self.y_axis = Axis::Log;
        self
    }
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
    pub fn legend(mut self, c: Corner) -> Self {
        self.legend = c;
        self
    }
    pub fn with(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
    pub fn note(mut self, text: impl Into<String>) -> Self {
        self.notes.push(text.into());
        self
    }
}

pub(super) fn draw_line_plot<DB: DrawingBackend>(
    ink: &Ink<DB>,
    area: &Area<DB>,
    p: &LinePlot,
) -> Result<(), String> {
    let xr = auto_range(
        p.series.iter().flat_map(|s| s.points.iter().map(|q| &q.0)),
        p.x_axis,
        p.x_range,
    );
    let yr = auto_range(
        p.series.iter().flat_map(|s| s.points.iter().map(|q| &q.1)),
        p.y_axis,
        p.y_range,
    );
    let layout = AxesLayout {
        title: &p.title,
        x_label: &p.x_label,
        y_label: &p.y_label,
        x_range: xr,
        y_range: yr,
        x_axis: p.x_axis,
        y_axis: p.y_axis,
        right_margin: 16,
    };
    let mut chart = axes(ink, area, &layout)?;
    for s in &p.series {
        draw_series(&mut chart, s, p.x_axis, p.y_axis)?;
    }
    legend_and_notes(ink, &chart, &p.series, p.legend, &p.notes)
}

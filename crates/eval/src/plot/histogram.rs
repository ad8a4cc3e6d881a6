//! Histograms with line overlays.

use plotters::prelude::*;

use super::area::{err, Area};
use super::axes::{auto_range, axes, draw_series, legend_and_notes, AxesLayout};
use super::style::{Axis, Corner, Rgb, Series};
use super::text::Ink;

/// A histogram (bars of `heights` between consecutive `edges`) with line
/// overlays such as a fitted density.
#[derive(Clone, Debug, Default)]
pub struct Histogram {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub edges: Vec<f64>,
    pub heights: Vec<f64>,
    pub color: Option<Rgb>,
    pub overlays: Vec<Series>,
    pub notes: Vec<String>,
}

impl Histogram {
    /// Density histogram of `samples` over `range` with `bins` bins (samples
    /// outside the range count towards the normalisation, not to any bar).
    pub fn density(
        title: impl Into<String>,
        x_label: impl Into<String>,
        samples: &[f64],
        bins: usize,
        range: (f64, f64),
    ) -> Self {
        let bins = bins.max(1);
        let w = (range.1 - range.0) / bins as f64;
        let mut counts = vec![0u64; bins];
        for &x in samples {
            let b = ((x - range.0) / w).floor();
            if b >= 0.0 && (b as usize) < bins {
                counts[b as usize] += 1;
            }
        }
        let n = samples.len().max(1) as f64;
        Histogram {
            title: title.into(),
            x_label: x_label.into(),
            y_label: "density".into(),
            edges: (0..=bins).map(|i| range.0 + i as f64 * w).collect(),
            heights: counts.iter().map(|&c| c as f64 / (n * w)).collect(),
            ..Default::default()
        }
    }
    pub fn overlay(mut self, s: Series) -> Self {
        self.overlays.push(s);
        self
    }
    pub fn note(mut self, text: impl Into<String>) -> Self {
        self.notes.push(text.into());
        self
    }
}

pub(super) fn draw_histogram<DB: DrawingBackend>(
    ink: &Ink<DB>,
    area: &Area<DB>,
    h: &Histogram,
) -> Result<(), String> {
    let xr = auto_range(h.edges.iter(), Axis::Linear, None);
    let top = h
        .heights
        .iter()
        .chain(
            h.overlays
                .iter()
                .flat_map(|s| s.points.iter().map(|q| &q.1)),
        )
        .fold(0.0f64, |a, &b| if b.is_finite() { a.max(b) } else { a });
    let yr = (0.0, if top > 0.0 { 1.08 * top } else { 1.0 });
    let layout = AxesLayout {
        title: &h.title,
        x_label: &h.x_label,
        y_label: &h.y_label,
        x_range: xr,
        y_range: yr,
        x_axis: Axis::Linear,
        y_axis: Axis::Linear,
        right_margin: 16,
    };
    let mut chart = axes(ink, area, &layout)?;
    let c = h.color.unwrap_or(Rgb(150, 170, 200)).to_plotters();
    chart
        .draw_series(
            h.heights.iter().enumerate().map(|(i, &v)| {
                Rectangle::new([(h.edges[i], 0.0), (h.edges[i + 1], v)], c.filled())
            }),
        )
        .map_err(err)?;
    for s in &h.overlays {
        draw_series(&mut chart, s, Axis::Linear, Axis::Linear)?;
    }
    legend_and_notes(ink, &chart, &h.overlays, Corner::UpperRight, &h.notes)
}

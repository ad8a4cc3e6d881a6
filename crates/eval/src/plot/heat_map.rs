//! Heat maps with a colour bar.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use super::area::{err, Area};
use super::axes::{axes, draw_series, legend_and_notes, ticks, AxesLayout};
use super::style::{Axis, Corner, Series};
use super::text::Ink;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourMap {
    /// Blue below 0, white at 0, red above; symmetric range.
    Diverging,
    /// Viridis-like, low to high.
    Sequential,
}

/// Cell values over a regular grid: `values[j * nx + i]` covers
/// x ∈ [x0 + i·dx, x0 + (i+1)·dx], y likewise, j = 0 the lowest row.
#[derive(Clone, Debug)]
pub struct HeatMap {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    pub nx: usize,
    pub ny: usize,
    pub values: Vec<f64>,
    pub map: ColourMap,
    /// Values mapped to the ends of the colour bar (clamped beyond).
    pub limits: (f64, f64),
    pub bar_label: String,
    pub overlays: Vec<Series>,
}

fn colour(map: ColourMap, t: f64) -> RGBColor {
    let lerp = |a: (f64, f64, f64), b: (f64, f64, f64), s: f64| {
        RGBColor(
            (a.0 + s * (b.0 - a.0)) as u8,
            (a.1 + s * (b.1 - a.1)) as u8,
            (a.2 + s * (b.2 - a.2)) as u8,
        )
    };
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.5
    };
    match map {
        ColourMap::Diverging => {
            let white = (247.0, 247.0, 247.0);
            if t < 0.5 {
                lerp((33.0, 102.0, 172.0), white, t / 0.5)
            } else {
                lerp(white, (178.0, 24.0, 43.0), (t - 0.5) / 0.5)
            }
        }
        ColourMap::Sequential => {
            const V: [(f64, f64, f64); 5] = [
                (68.0, 1.0, 84.0),
                (59.0, 82.0, 139.0),
                (33.0, 145.0, 140.0),
                (94.0, 201.0, 98.0),
                (253.0, 231.0, 37.0),
            ];
            let s = t * 4.0;
            let i = (s.floor() as usize).min(3);
            lerp(V[i], V[i + 1], s - i as f64)
        }
    }
}

pub(super) fn draw_heat_map<DB: DrawingBackend>(
    ink: &Ink<DB>,
    area: &Area<DB>,
    h: &HeatMap,
) -> Result<(), String> {
    let (w, _) = area.dim_in_pixel();
    let (main, bar) = area.split_horizontally(w.saturating_sub(96));
    let layout = AxesLayout {
        title: &h.title,
        x_label: &h.x_label,
        y_label: &h.y_label,
        x_range: h.x_range,
        y_range: h.y_range,
        x_axis: Axis::Linear,
        y_axis: Axis::Linear,
        right_margin: 8,
    };
    let mut chart = axes(ink, &main, &layout)?;
    let dx = (h.x_range.1 - h.x_range.0) / h.nx as f64;
    let dy = (h.y_range.1 - h.y_range.0) / h.ny as f64;
    let (lo, hi) = h.limits;
    let norm = |v: f64| (v - lo) / (hi - lo);
    chart
        .draw_series(
            (0..h.ny)
                .flat_map(|j| (0..h.nx).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let (x0, y0) = (h.x_range.0 + i as f64 * dx, h.y_range.0 + j as f64 * dy);
                    Rectangle::new(
                        [(x0, y0), (x0 + dx, y0 + dy)],
                        colour(h.map, norm(h.values[j * h.nx + i])).filled(),
                    )
                }),
        )
        .map_err(err)?;
    for s in &h.overlays {
        let clipped = Series {
            points: s
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| {
                    x >= h.x_range.0 && x <= h.x_range.1 && y >= h.y_range.0 && y <= h.y_range.1
                })
                .collect(),
            ..s.clone()
        };
        draw_series(&mut chart, &clipped, Axis::Linear, Axis::Linear)?;
    }
    legend_and_notes(ink, &chart, &h.overlays, Corner::UpperLeft, &[])?;
    // Colour bar, aligned with the plotting area.
    let (_, py) = chart.plotting_area().get_pixel_range();
    colour_bar(ink, &bar, h, py)
}

/// The colour bar right of the plot, spanning the plotting area's rows
/// `py`, with its ticks and its label.
fn colour_bar<DB: DrawingBackend>(
    ink: &Ink<DB>,
    bar: &Area<DB>,
    h: &HeatMap,
    py: std::ops::Range<i32>,
) -> Result<(), String> {
    let (lo, hi) = h.limits;
    let (bx, _) = bar.get_base_pixel();
    let (x0, x1) = (bx + 6, bx + 26);
    let steps = 128;
    let span = (py.end - py.start) as f64;
    for k in 0..steps {
        let ya = py.end as f64 - span * k as f64 / steps as f64;
        let yb = py.end as f64 - span * (k + 1) as f64 / steps as f64;
        let c = colour(h.map, (k as f64 + 0.5) / steps as f64);
        ink.root
            .draw(&Rectangle::new(
                [(x0, yb.floor() as i32), (x1, ya.ceil() as i32)],
                c.filled(),
            ))
            .map_err(err)?;
    }
    ink.root
        .draw(&Rectangle::new(
            [(x0, py.start), (x1, py.end)],
            ShapeStyle::from(&BLACK).stroke_width(1),
        ))
        .map_err(err)?;
    let bt = ticks(lo, hi, Axis::Linear);
    for (v, l) in bt.major.iter().zip(&bt.labels) {
        let y = py.end - ((v - lo) / (hi - lo) * span).round() as i32;
        ink.root
            .draw(&PathElement::new(vec![(x1, y), (x1 + 4, y)], BLACK))
            .map_err(err)?;
        ink.text(l, (x1 + 9, y), 1, HPos::Left, VPos::Center, false)?;
    }
    // The bar's label reads upwards right of its tick labels (as in
    // matplotlib), where no panel title can run into it.
    let tick_w = bt.labels.iter().map(|l| ink.width(l, 1)).max().unwrap_or(0);
    let (bar_w, _) = bar.dim_in_pixel();
    let label_x = (x1 + 9 + tick_w + 4).min(bx + bar_w as i32 - 17);
    ink.text(
        &h.bar_label,
        (label_x, (py.start + py.end) / 2),
        1,
        HPos::Center,
        VPos::Top,
        true,
    )
}

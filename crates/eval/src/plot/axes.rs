//! Axes shared by every panel: ticks, ranges, frame and labels, data
//! series and the legend.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use super::area::{err, Area, Chart};
use super::style::{Axis, Corner, Mark, Series};
use super::text::Ink;

/// Axis ticks: positions in plot coordinates (log10 for log axes) and labels.
pub(super) struct Ticks {
    pub(super) major: Vec<f64>,
    pub(super) minor: Vec<f64>,
    pub(super) labels: Vec<String>,
}

pub(super) fn ticks(lo: f64, hi: f64, axis: Axis) -> Ticks {
    match axis {
        Axis::Linear => {
            let raw = (hi - lo) / 6.0;
            let mag = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 2.5, 5.0, 10.0]
                .iter()
                .map(|m| m * mag)
                .find(|s| *s >= raw)
                .unwrap_or(10.0 * mag);
            let first = (lo / step).ceil() as i64;
            let last = (hi / step).floor() as i64;
            let major: Vec<f64> = (first..=last).map(|k| k as f64 * step).collect();
            let decimals = (-(step.log10().floor()) as i32
                + if (step / mag - 2.5).abs() < 1e-9 {
                    1
                } else {
                    0
                })
            .max(0) as usize;
            let labels = major
                .iter()
                .map(|v| {
                    let v = if v.abs() < step * 1e-9 { 0.0 } else { *v };
                    format!("{v:.decimals$}")
                })
                .collect();
            Ticks {
                major,
                minor: Vec::new(),
                labels,
            }
        }
        Axis::Log => {
            let (e0, e1) = (lo.ceil() as i32, hi.floor() as i32);
            let mut major: Vec<f64> = (e0..=e1).map(|e| e as f64).collect();
            let mut minor = Vec::new();
            for e in (lo.floor() as i32)..=(hi.ceil() as i32) {
                for k in 2..10 {
                    let v = e as f64 + (k as f64).log10();
                    if v >= lo && v <= hi {
                        minor.push(v);
                    }
                }
            }
            if major.len() < 2 {
                // Less than two decades: label the 2× and 5× points too.
                major.extend(minor.iter().copied().filter(|v| {
                    let f = 10f64.powf(v - v.floor());
                    (f - 2.0).abs() < 1e-6 || (f - 5.0).abs() < 1e-6
                }));
                major.sort_by(f64::total_cmp);
            }
            let labels = major.iter().map(|&v| fmt_log(10f64.powf(v))).collect();
            Ticks {
                major,
                minor,
                labels,
            }
        }
    }
}

fn fmt_log(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if (1e-4..1e5).contains(&r) {
        let s = format!("{r:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("1e{}", v.log10().round() as i32)
    }
}

fn to_plot(v: f64, axis: Axis) -> Option<f64> {
    match axis {
        Axis::Linear => v.is_finite().then_some(v),
        Axis::Log => (v > 0.0 && v.is_finite()).then(|| v.log10()),
    }
}

/// Data range of the series in plot coordinates, padded.
pub(super) fn auto_range<'a>(
    vals: impl Iterator<Item = &'a f64>,
    axis: Axis,
    given: Option<(f64, f64)>,
) -> (f64, f64) {
    if let Some((a, b)) = given {
        let (a, b) = (
            to_plot(a, axis).unwrap_or(-1.0),
            to_plot(b, axis).unwrap_or(1.0),
        );
        return (a.min(b), a.max(b));
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter_map(|v| to_plot(*v, axis)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-12 {
        let d = if lo.abs() > 0.0 { 0.1 * lo.abs() } else { 1.0 };
        return (lo - d, hi + d);
    }
    let pad = 0.04 * (hi - lo);
    (lo - pad, hi + pad)
}

/// What [`axes`] lays out: the panel's title and axis descriptions, the
/// ranges in plot coordinates (log10 for log axes), the scales, and the
/// space right of the plot (a heat map's colour bar needs less).
pub(super) struct AxesLayout<'s> {
    pub(super) title: &'s str,
    pub(super) x_label: &'s str,
    pub(super) y_label: &'s str,
    pub(super) x_range: (f64, f64),
    pub(super) y_range: (f64, f64),
    pub(super) x_axis: Axis,
    pub(super) y_axis: Axis,
    pub(super) right_margin: u32,
}

/// Builds the chart with mesh and ticks, draws tick labels, axis
/// descriptions and the title; returns the chart for the data.
pub(super) fn axes<'a, DB: DrawingBackend>(
    ink: &Ink<DB>,
    area: &'a Area<DB>,
    layout: &AxesLayout,
) -> Result<Chart<'a, DB>, String> {
    let (xr, yr) = (layout.x_range, layout.y_range);
    let xt = ticks(xr.0, xr.1, layout.x_axis);
    let yt = ticks(yr.0, yr.1, layout.y_axis);
    let y_label_w = yt.labels.iter().map(|l| ink.width(l, 1)).max().unwrap_or(0) as u32;
    let mut chart = ChartBuilder::on(area)
        .margin_top(if layout.title.is_empty() { 10 } else { 34 })
        .margin_right(layout.right_margin)
        .margin_left(8)
        .margin_bottom(6)
        .x_label_area_size(44)
        .y_label_area_size(y_label_w + 34)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(err)?;
    draw_grid(&mut chart, &xt, &yt, xr, yr)?;
    draw_ticks(ink, &chart, &xt, &yt, xr, yr)?;
    draw_labels(ink, area, &chart, layout, y_label_w)?;
    Ok(chart)
}

/// Minor and major grid lines (plotters' mesh would also want to draw the
/// labels, which this module places itself).
fn draw_grid<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    xt: &Ticks,
    yt: &Ticks,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), String> {
    let grid = |v: &[f64], c: RGBColor| -> Vec<PathElement<(f64, f64)>> {
        v.iter()
            .map(|&x| PathElement::new(vec![(x, yr.0), (x, yr.1)], c))
            .collect()
    };
    let hgrid = |v: &[f64], c: RGBColor| -> Vec<PathElement<(f64, f64)>> {
        v.iter()
            .map(|&y| PathElement::new(vec![(xr.0, y), (xr.1, y)], c))
            .collect()
    };
    let light = RGBColor(238, 238, 238);
    let bold = RGBColor(205, 205, 205);
    chart.draw_series(grid(&xt.minor, light)).map_err(err)?;
    chart.draw_series(hgrid(&yt.minor, light)).map_err(err)?;
    chart.draw_series(grid(&xt.major, bold)).map_err(err)?;
    chart.draw_series(hgrid(&yt.major, bold)).map_err(err)?;
    Ok(())
}

/// The frame round the plotting area, tick marks and tick labels.
fn draw_ticks<DB: DrawingBackend>(
    ink: &Ink<DB>,
    chart: &Chart<DB>,
    xt: &Ticks,
    yt: &Ticks,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), String> {
    let (px, py) = chart.plotting_area().get_pixel_range();
    let root = ink.root;
    let frame = ShapeStyle::from(&BLACK).stroke_width(1);
    root.draw(&Rectangle::new(
        [(px.start, py.start), (px.end - 1, py.end - 1)],
        frame,
    ))
    .map_err(err)?;
    for (v, l) in xt.major.iter().zip(&xt.labels) {
        let (x, _) = chart.backend_coord(&(*v, yr.0));
        root.draw(&PathElement::new(vec![(x, py.end), (x, py.end + 5)], frame))
            .map_err(err)?;
        ink.text(l, (x, py.end + 8), 1, HPos::Center, VPos::Top, false)?;
    }
    for (v, l) in yt.major.iter().zip(&yt.labels) {
        let (_, y) = chart.backend_coord(&(xr.0, *v));
        root.draw(&PathElement::new(
            vec![(px.start - 5, y), (px.start, y)],
            frame,
        ))
        .map_err(err)?;
        ink.text(l, (px.start - 8, y), 1, HPos::Right, VPos::Center, false)?;
    }
    Ok(())
}

/// The axis descriptions (the y one reading upwards, left of tick labels
/// `y_label_w` wide) and the title, centred over the plot.
fn draw_labels<DB: DrawingBackend>(
    ink: &Ink<DB>,
    area: &Area<DB>,
    chart: &Chart<DB>,
    layout: &AxesLayout,
    y_label_w: u32,
) -> Result<(), String> {
    let (px, py) = chart.plotting_area().get_pixel_range();
    let cx = (px.start + px.end) / 2;
    ink.text(
        layout.x_label,
        (cx, py.end + 24),
        1,
        HPos::Center,
        VPos::Top,
        false,
    )?;
    let cy = (py.start + py.end) / 2;
    ink.text(
        layout.y_label,
        (px.start - 16 - y_label_w as i32, cy),
        1,
        HPos::Center,
        VPos::Bottom,
        true,
    )?;
    let (aw, _) = area.dim_in_pixel();
    let (title, scale) = ink.fitted(layout.title, 2, aw as i32 - 8);
    let centre = {
        // Centred over the plot, moved in when that would cut the text.
        let half = ink.width(&title, scale) / 2;
        let (x0, x1) = (area.get_base_pixel().0, area.get_base_pixel().0 + aw as i32);
        cx.clamp(x0 + 4 + half, (x1 - 4 - half).max(x0 + 4 + half))
    };
    ink.text(
        &title,
        (centre, py.start - 26),
        scale,
        HPos::Center,
        VPos::Top,
        false,
    )
}

pub(super) fn draw_series<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    s: &Series,
    xa: Axis,
    ya: Axis,
) -> Result<(), String> {
    let pts: Vec<(f64, f64)> = s
        .points
        .iter()
        .filter_map(|&(x, y)| Some((to_plot(x, xa)?, to_plot(y, ya)?)))
        .collect();
    let c = s.color.to_plotters();
    let style = ShapeStyle::from(&c).stroke_width(2);
    match s.mark {
        Mark::Line => {
            chart
                .draw_series(LineSeries::new(pts, style))
                .map_err(err)?;
        }
        Mark::Dashed => {
            chart
                .draw_series(DashedLineSeries::new(pts, 7, 5, style))
                .map_err(err)?;
        }
        Mark::Points => {
            chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, c.filled())))
                .map_err(err)?;
        }
        Mark::LinePoints => {
            chart
                .draw_series(LineSeries::new(pts.clone(), style))
                .map_err(err)?;
            chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, c.filled())))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// Legend box and free-text notes inside the plotting area.
pub(super) fn legend_and_notes<DB: DrawingBackend>(
    ink: &Ink<DB>,
    chart: &Chart<DB>,
    series: &[Series],
    corner: Corner,
    notes: &[String],
) -> Result<(), String> {
    let (px, py) = chart.plotting_area().get_pixel_range();
    let mut y = py.start + 8;
    for n in notes {
        ink.text(n, (px.start + 8, y), 1, HPos::Left, VPos::Top, false)?;
        y += 14;
    }
    let entries: Vec<&Series> = series.iter().filter(|s| s.label.is_some()).collect();
    if entries.is_empty() {
        return Ok(());
    }
    let text_w = entries
        .iter()
        .map(|s| ink.width(s.label.as_deref().unwrap_or(""), 1))
        .max()
        .unwrap_or(0);
    let (w, h) = (text_w + 44, entries.len() as i32 * 15 + 8);
    let x0 = match corner {
        Corner::UpperRight | Corner::LowerRight => px.end - w - 6,
        _ => px.start + 6,
    };
    let y0 = match corner {
        Corner::UpperRight | Corner::UpperLeft => {
            py.start
                + 6
                + if notes.is_empty() || x0 > px.start + 6 {
                    0
                } else {
                    notes.len() as i32 * 14
                }
        }
        _ => py.end - h - 6,
    };
    let root = ink.root;
    root.draw(&Rectangle::new(
        [(x0, y0), (x0 + w, y0 + h)],
        WHITE.mix(0.9).filled(),
    ))
    .map_err(err)?;
    root.draw(&Rectangle::new(
        [(x0, y0), (x0 + w, y0 + h)],
        ShapeStyle::from(&BLACK).stroke_width(1),
    ))
    .map_err(err)?;
    for (k, s) in entries.iter().enumerate() {
        legend_entry(ink, s, x0, y0 + 11 + k as i32 * 15)?;
    }
    Ok(())
}

/// One legend entry at height `yc`: the series' mark, then its label.
fn legend_entry<DB: DrawingBackend>(
    ink: &Ink<DB>,
    s: &Series,
    x0: i32,
    yc: i32,
) -> Result<(), String> {
    let root = ink.root;
    let c = s.color.to_plotters();
    let style = ShapeStyle::from(&c).stroke_width(2);
    let (a, b) = ((x0 + 6, yc), (x0 + 30, yc));
    match s.mark {
        Mark::Line => root
            .draw(&PathElement::new(vec![a, b], style))
            .map_err(err)?,
        Mark::Dashed => {
            root.draw(&PathElement::new(vec![a, (x0 + 14, yc)], style))
                .map_err(err)?;
            root.draw(&PathElement::new(vec![(x0 + 20, yc), b], style))
                .map_err(err)?;
        }
        Mark::Points => root
            .draw(&Circle::new((x0 + 18, yc), 3, c.filled()))
            .map_err(err)?,
        Mark::LinePoints => {
            root.draw(&PathElement::new(vec![a, b], style))
                .map_err(err)?;
            root.draw(&Circle::new((x0 + 18, yc), 3, c.filled()))
                .map_err(err)?;
        }
    }
    ink.text(
        s.label.as_deref().unwrap_or(""),
        (x0 + 36, yc),
        1,
        HPos::Left,
        VPos::Center,
        false,
    )
}

//! Small plotting helpers on top of `plotters`: line plots (linear or log
//! axes), histograms with overlays, heat maps with a colour bar, arranged in
//! a grid of panels and written as SVG and PNG.
//!
//! plotters is built without fonts, so its bitmap backend cannot draw text.
//! Every piece of text (titles, tick labels, axis descriptions, legends) is
//! therefore placed by this module itself, at the same pixel positions in
//! both outputs: as `<text>` elements in the SVG and with a built-in 5×7
//! bitmap font in the PNG. plotters draws only lines, marks and fills.

mod bitmap_font;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const GREY: Rgb = Rgb(120, 120, 120);

    fn to_plotters(self) -> RGBColor {
        RGBColor(self.0, self.1, self.2)
    }
}

/// Colour-blind-safe categorical colours (Okabe–Ito).
pub fn palette(i: usize) -> Rgb {
    const P: [Rgb; 8] = [
        Rgb(0, 114, 178),
        Rgb(213, 94, 0),
        Rgb(0, 158, 115),
        Rgb(204, 121, 167),
        Rgb(230, 159, 0),
        Rgb(86, 180, 233),
        Rgb(0, 0, 0),
        Rgb(240, 228, 66),
    ];
    P[i % P.len()]
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Axis {
    #[default]
    Linear,
    /// Base-10 logarithmic; non-positive values are dropped.
    Log,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    Line,
    Dashed,
    Points,
    LinePoints,
}

/// One data series of a line plot or an overlay.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend entry; `None` keeps the series out of the legend.
    pub label: Option<String>,
    pub points: Vec<(f64, f64)>,
    pub color: Rgb,
    pub mark: Mark,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, color: Rgb, mark: Mark) -> Self {
        let label = label.into();
        Series {
            label: (!label.is_empty()).then_some(label),
            points,
            color,
            mark,
        }
    }
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>, color: Rgb) -> Self {
        Self::new(label, points, color, Mark::Line)
    }
    pub fn dashed(label: impl Into<String>, points: Vec<(f64, f64)>, color: Rgb) -> Self {
        Self::new(label, points, color, Mark::Dashed)
    }
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>, color: Rgb) -> Self {
        Self::new(label, points, color, Mark::Points)
    }
}

/// Corner of the plotting area holding the legend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Corner {
    #[default]
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
}

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

pub enum Panel {
    Line(LinePlot),
    Histogram(Histogram),
    HeatMap(HeatMap),
}

impl From<LinePlot> for Panel {
    fn from(p: LinePlot) -> Self {
        Panel::Line(p)
    }
}
impl From<Histogram> for Panel {
    fn from(p: Histogram) -> Self {
        Panel::Histogram(p)
    }
}
impl From<HeatMap> for Panel {
    fn from(p: HeatMap) -> Self {
        Panel::HeatMap(p)
    }
}

/// Panels in a grid, `columns` wide, each `panel_size` pixels.
pub struct Figure {
    pub title: Option<String>,
    pub panels: Vec<Panel>,
    pub columns: usize,
    pub panel_size: (u32, u32),
}

impl Figure {
    pub fn new(columns: usize) -> Self {
        Figure {
            title: None,
            panels: Vec::new(),
            columns: columns.max(1),
            panel_size: (560, 420),
        }
    }
    pub fn title(mut self, t: impl Into<String>) -> Self {
        self.title = Some(t.into());
        self
    }
    pub fn panel_size(mut self, w: u32, h: u32) -> Self {
        self.panel_size = (w, h);
        self
    }
    pub fn with(mut self, p: impl Into<Panel>) -> Self {
        self.panels.push(p.into());
        self
    }

    fn size(&self) -> (u32, u32) {
        let rows = self.panels.len().div_ceil(self.columns).max(1) as u32;
        let cols = self.columns.min(self.panels.len().max(1)) as u32;
        (
            cols * self.panel_size.0,
            rows * self.panel_size.1 + if self.title.is_some() { TITLE_H } else { 0 },
        )
    }

    /// Writes `<stem>.svg` and `<stem>.png`; returns both paths.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, String> {
        let svg = stem.with_extension("svg");
        let png = stem.with_extension("png");
        {
            let root = SVGBackend::new(&svg, self.size()).into_drawing_area();
            self.render(&root, Target::Svg)?;
            root.present().map_err(err)?;
        }
        {
            let root = BitMapBackend::new(&png, self.size()).into_drawing_area();
            self.render(&root, Target::Png)?;
            root.present().map_err(err)?;
        }
        Ok(vec![svg, png])
    }

    fn render<DB: DrawingBackend>(&self, root: &Area<DB>, target: Target) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;
        let ink = Ink { root, target };
        let body = if let Some(t) = &self.title {
            let (w, _) = self.size();
            ink.text(t, ((w / 2) as i32, 8), 2, HPos::Center, VPos::Top, false)?;
            root.split_vertically(TITLE_H).1
        } else {
            root.clone()
        };
        let rows = self.panels.len().div_ceil(self.columns).max(1);
        let areas = body.split_evenly((rows, self.columns));
        for (panel, area) in self.panels.iter().zip(areas.iter()) {
            match panel {
                Panel::Line(p) => draw_line_plot(&ink, area, p)?,
                Panel::Histogram(h) => draw_histogram(&ink, area, h)?,
                Panel::HeatMap(h) => draw_heat_map(&ink, area, h)?,
            }
        }
        Ok(())
    }
}

const TITLE_H: u32 = 34;

type Area<DB> = DrawingArea<DB, plotters::coord::Shift>;
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn err(e: impl std::fmt::Display) -> String {
    format!("plot: {e}")
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Target {
    Svg,
    Png,
}

/// Draws text at absolute pixel positions on the figure's root area.
struct Ink<'r, DB: DrawingBackend> {
    root: &'r Area<DB>,
    target: Target,
}

impl<DB: DrawingBackend> Ink<'_, DB> {
    /// `scale` 1 is tick-label size, 2 titles and axis descriptions.
    /// `vertical` text reads bottom to top.
    fn text(
        &self,
        s: &str,
        pos: (i32, i32),
        scale: u32,
        h: HPos,
        v: VPos,
        vertical: bool,
    ) -> Result<(), String> {
        if s.is_empty() {
            return Ok(());
        }
        match self.target {
            Target::Svg => {
                let style = TextStyle::from(("sans-serif", 12.0 * 1.24 * scale as f64).into_font())
                    .pos(Pos::new(h, v))
                    .transform(if vertical {
                        FontTransform::Rotate270
                    } else {
                        FontTransform::None
                    })
                    .color(&BLACK);
                self.root
                    .draw(&Text::new(s.to_string(), pos, style))
                    .map_err(err)
            }
            Target::Png => {
                let (w, ht) = bitmap_font::text_size(s, scale);
                let dx = match h {
                    HPos::Left => 0,
                    HPos::Center => -(w as i32) / 2,
                    HPos::Right => -(w as i32),
                };
                let dy = match v {
                    VPos::Top => 0,
                    VPos::Center => -(ht as i32) / 2,
                    VPos::Bottom => -(ht as i32),
                };
                let mut res = Ok(());
                bitmap_font::rasterise(s, scale, |x, y| {
                    let (lx, ly) = (x as i32 + dx, y as i32 + dy);
                    let p = if vertical {
                        (pos.0 + ly, pos.1 - lx)
                    } else {
                        (pos.0 + lx, pos.1 + ly)
                    };
                    if res.is_ok() {
                        res = self.root.draw_pixel(p, &BLACK).map_err(err);
                    }
                });
                res
            }
        }
    }

    fn width(&self, s: &str, scale: u32) -> i32 {
        bitmap_font::text_size(s, scale).0 as i32
    }
}

/// Axis ticks: positions in plot coordinates (log10 for log axes) and labels.
struct Ticks {
    major: Vec<f64>,
    minor: Vec<f64>,
    labels: Vec<String>,
}

fn ticks(lo: f64, hi: f64, axis: Axis) -> Ticks {
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
fn auto_range<'a>(
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

/// Builds the chart with mesh and ticks, draws tick labels, axis
/// descriptions and the title; returns the chart for the data.
#[allow(clippy::too_many_arguments)]
fn axes<'a, DB: DrawingBackend>(
    ink: &Ink<DB>,
    area: &'a Area<DB>,
    title: &str,
    x_label: &str,
    y_label: &str,
    xr: (f64, f64),
    yr: (f64, f64),
    xa: Axis,
    ya: Axis,
    right_margin: u32,
) -> Result<Chart<'a, DB>, String> {
    let xt = ticks(xr.0, xr.1, xa);
    let yt = ticks(yr.0, yr.1, ya);
    let y_label_w = yt.labels.iter().map(|l| ink.width(l, 1)).max().unwrap_or(0) as u32;
    let mut chart = ChartBuilder::on(area)
        .margin_top(if title.is_empty() { 10 } else { 34 })
        .margin_right(right_margin)
        .margin_left(8)
        .margin_bottom(6)
        .x_label_area_size(44)
        .y_label_area_size(y_label_w + 34)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(err)?;
    // Grid, frame and tick marks (plotters' mesh would also want to draw
    // the labels, which this module places itself).
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
    let cx = (px.start + px.end) / 2;
    ink.text(
        x_label,
        (cx, py.end + 24),
        1,
        HPos::Center,
        VPos::Top,
        false,
    )?;
    let cy = (py.start + py.end) / 2;
    ink.text(
        y_label,
        (px.start - 16 - y_label_w as i32, cy),
        1,
        HPos::Center,
        VPos::Bottom,
        true,
    )?;
    ink.text(
        title,
        (cx, py.start - 26),
        2,
        HPos::Center,
        VPos::Top,
        false,
    )?;
    Ok(chart)
}

fn draw_series<DB: DrawingBackend>(
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
fn legend_and_notes<DB: DrawingBackend>(
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
        let yc = y0 + 11 + k as i32 * 15;
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
        )?;
    }
    Ok(())
}

fn draw_line_plot<DB: DrawingBackend>(
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
    let mut chart = axes(
        ink, area, &p.title, &p.x_label, &p.y_label, xr, yr, p.x_axis, p.y_axis, 16,
    )?;
    for s in &p.series {
        draw_series(&mut chart, s, p.x_axis, p.y_axis)?;
    }
    legend_and_notes(ink, &chart, &p.series, p.legend, &p.notes)
}

fn draw_histogram<DB: DrawingBackend>(
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
    let mut chart = axes(
        ink,
        area,
        &h.title,
        &h.x_label,
        &h.y_label,
        xr,
        yr,
        Axis::Linear,
        Axis::Linear,
        16,
    )?;
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

fn draw_heat_map<DB: DrawingBackend>(
    ink: &Ink<DB>,
    area: &Area<DB>,
    h: &HeatMap,
) -> Result<(), String> {
    let (w, _) = area.dim_in_pixel();
    let (main, bar) = area.split_horizontally(w.saturating_sub(96));
    let mut chart = axes(
        ink,
        &main,
        &h.title,
        &h.x_label,
        &h.y_label,
        h.x_range,
        h.y_range,
        Axis::Linear,
        Axis::Linear,
        8,
    )?;
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
    ink.text(
        &h.bar_label,
        ((x0 + x1) / 2, py.start - 8),
        1,
        HPos::Center,
        VPos::Bottom,
        false,
    )
}

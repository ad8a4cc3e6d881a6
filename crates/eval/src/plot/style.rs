//! The style and series types every plot file shares: colours, axis kinds,
//! marks, data series and legend corners.

use plotters::prelude::*;

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const GREY: Rgb = Rgb(120, 120, 120);

    pub(super) fn to_plotters(self) -> RGBColor {
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

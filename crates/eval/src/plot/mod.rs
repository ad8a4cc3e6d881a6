//! Small plotting helpers on top of `plotters`: line plots (linear or log
//! axes), histograms with overlays, heat maps with a colour bar, arranged in
//! a grid of panels and written as SVG and PNG.
//!
//! plotters is built without fonts, so its bitmap backend cannot draw text.
//! Every piece of text (titles, tick labels, axis descriptions, legends) is
//! therefore placed by this module itself, at the same pixel positions in
//! both outputs: as `<text>` elements in the SVG and, in the PNG, in an
//! embedded proportional font (Ubuntu Light, anti-aliased by `ab_glyph`;
//! see `font.rs`), measured with the same metrics so titles fit. plotters
//! draws only lines, marks and fills.

mod area;
mod axes;
mod font;
mod heat_map;
mod histogram;
mod line;
mod style;
mod text;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};
use std::path::{Path, PathBuf};

use area::{err, Area};
use heat_map::draw_heat_map;
pub use heat_map::{ColourMap, HeatMap};
use histogram::draw_histogram;
pub use histogram::Histogram;
use line::draw_line_plot;
pub use line::LinePlot;
pub use style::{palette, Axis, Corner, Mark, Rgb, Series};
use text::{Ink, Target};

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
        // Drawn into memory and encoded by the `image` crate the workspace
        // already has (plotters' own encoder would build a second version).
        let (w, h) = self.size();
        let mut rgb = vec![0u8; 3 * w as usize * h as usize];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
            self.render(&root, Target::Png)?;
            root.present().map_err(err)?;
        }
        image::save_buffer(&png, &rgb, w, h, image::ExtendedColorType::Rgb8)
            .map_err(|e| format!("{}: {e}", png.display()))?;
        Ok(vec![svg, png])
    }

    fn render<DB: DrawingBackend>(&self, root: &Area<DB>, target: Target) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;
        let ink = Ink { root, target };
        let body = if let Some(t) = &self.title {
            let (w, _) = self.size();
            let (t, scale) = ink.fitted(t, 2, w as i32 - 16);
            ink.text(
                &t,
                ((w / 2) as i32, 8),
                scale,
                HPos::Center,
                VPos::Top,
                false,
            )?;
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

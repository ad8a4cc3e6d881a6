//! Text at pixel positions: `<text>` elements in the SVG, the embedded
//! proportional font ([`super::font`]) anti-aliased into the PNG.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::area::{err, Area};
use super::font;

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Target {
    Svg,
    Png,
}

/// Draws text at absolute pixel positions on the figure's root area.
pub(super) struct Ink<'r, DB: DrawingBackend> {
    pub(super) root: &'r Area<DB>,
    pub(super) target: Target,
}

impl<DB: DrawingBackend> Ink<'_, DB> {
    /// `scale` 1 is tick-label size, 2 titles and axis descriptions.
    /// `vertical` text reads bottom to top.
    pub(super) fn text(
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
                let family = format!("{}, sans-serif", font::FAMILY);
                let style = TextStyle::from((family.as_str(), font::px(scale) as f64).into_font())
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
                let (w, ht) = font::text_size(s, scale);
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
                font::rasterise(s, scale, |x, y, coverage| {
                    let (lx, ly) = (x as i32 + dx, y as i32 + dy);
                    let p = if vertical {
                        (pos.0 + ly, pos.1 - lx)
                    } else {
                        (pos.0 + lx, pos.1 + ly)
                    };
                    if res.is_ok() {
                        res = self
                            .root
                            .draw_pixel(p, &BLACK.mix(coverage as f64))
                            .map_err(err);
                    }
                });
                res
            }
        }
    }

    /// A title that fits in `max_w` pixels: at `scale` when it fits, else
    /// at tick-label size, else cut with an ellipsis at tick-label size.
    pub(super) fn fitted(&self, s: &str, scale: u32, max_w: i32) -> (String, u32) {
        if self.width(s, scale) <= max_w {
            return (s.to_string(), scale);
        }
        if self.width(s, 1) <= max_w {
            return (s.to_string(), 1);
        }
        let mut cut: Vec<char> = s.chars().collect();
        while !cut.is_empty() {
            cut.pop();
            let t: String = cut.iter().collect::<String>().trim_end().to_string() + "…";
            if self.width(&t, 1) <= max_w {
                return (t, 1);
            }
        }
        (String::new(), 1)
    }

    pub(super) fn width(&self, s: &str, scale: u32) -> i32 {
        font::text_size(s, scale).0 as i32
    }
}

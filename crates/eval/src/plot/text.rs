//! Text at pixel positions: `<text>` elements in the SVG, the built-in
//! bitmap font in the PNG.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::area::{err, Area};
use super::bitmap_font;

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

    pub(super) fn width(&self, s: &str, scale: u32) -> i32 {
        bitmap_font::text_size(s, scale).0 as i32
    }
}

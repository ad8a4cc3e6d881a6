//! Text for PNG plots in a real proportional font: Ubuntu Light (the sans
//! face egui ships, embedded through `epaint_default_fonts`, Ubuntu Font
//! Licence), outlined and anti-aliased by `ab_glyph`. No system fonts are
//! needed, and the PNG and the viewer read alike. (The SVG names the same
//! family, falling back to the reader's sans-serif.)

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use std::sync::OnceLock;

/// The family the SVG asks for first.
pub const FAMILY: &str = "Ubuntu";

fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| {
        FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT)
            .expect("the embedded Ubuntu Light font parses")
    })
}

/// Pixel height (ascent − descent) of text at `scale`: 1 for tick labels,
/// 2 for titles and axis descriptions.
pub fn px(scale: u32) -> f32 {
    match scale {
        0 | 1 => 13.0,
        s => 9.0 * s as f32,
    }
}

/// Width and height in pixels of `s` on one line.
pub fn text_size(s: &str, scale: u32) -> (u32, u32) {
    let f = font().as_scaled(PxScale::from(px(scale)));
    let mut w = 0.0;
    let mut prev = None;
    for c in s.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    (w.ceil() as u32, (f.ascent() - f.descent()).ceil() as u32)
}

/// Calls `plot(x, y, coverage)` for every pixel the text covers, with
/// (0, 0) the top-left corner of its [`text_size`] box and coverage in
/// (0, 1].
pub fn rasterise(s: &str, scale: u32, mut plot: impl FnMut(u32, u32, f32)) {
    let f = font().as_scaled(PxScale::from(px(scale)));
    let (mut x, baseline) = (0.0f32, f.ascent());
    let mut prev = None;
    for c in s.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            x += f.kern(p, id);
        }
        let glyph = id.with_scale_and_position(px(scale), ab_glyph::point(x, baseline));
        if let Some(outline) = font().outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, cov| {
                let (px_, py) = (b.min.x as i32 + gx as i32, b.min.y as i32 + gy as i32);
                if cov > 0.0 && px_ >= 0 && py >= 0 {
                    plot(px_ as u32, py as u32, cov.min(1.0));
                }
            });
        }
        x += f.h_advance(id);
        prev = Some(id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proportional_widths_and_ink_inside_the_box() {
        let (wi, h) = text_size("iiii", 1);
        let (ww, _) = text_size("WWWW", 1);
        assert!(ww > 2 * wi, "proportional: iiii {wi} px, WWWW {ww} px");
        assert!((12..=18).contains(&h), "{h}");
        let (w, h) = text_size("MSE vs time (s)", 2);
        let (mut n, mut max_x, mut max_y) = (0, 0, 0);
        rasterise("MSE vs time (s)", 2, |x, y, c| {
            assert!(c > 0.0 && c <= 1.0);
            n += 1;
            max_x = max_x.max(x);
            max_y = max_y.max(y);
        });
        assert!(
            n > 100 && max_x <= w + 1 && max_y <= h + 1,
            "{n} {max_x}/{w} {max_y}/{h}"
        );
    }
}

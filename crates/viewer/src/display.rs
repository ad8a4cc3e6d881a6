//! From snapshots to the pixels on screen: the tone-mapped image, the
//! false-colour map of per-pixel relative standard error, and the
//! split-screen of two sessions (left half of one, right half of the
//! other).

use crate::session::Snapshot;
use fogbank::image::{luminance, ToneMapping};

/// What the image area shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Overlay {
    /// The tone-mapped image.
    Image,
    /// Relative standard error of each pixel's mean, √Var[mean] / mean
    /// (luminance), in false colour from 0 (dark blue) to [`REL_ERR_MAX`]
    /// and above (yellow).
    RelativeError,
}

/// The top of the relative-error colour scale.
pub const REL_ERR_MAX: f32 = 0.2;

/// Viridis at `t` ∈ [0, 1], from five of its stops, linearly between.
pub fn viridis(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let x = t.clamp(0.0, 1.0) * 4.0;
    let i = (x as usize).min(3);
    let f = x - i as f32;
    std::array::from_fn(|c| (STOPS[i][c] + (STOPS[i + 1][c] - STOPS[i][c]) * f + 0.5) as u8)
}

/// Relative standard error of pixel `i` (∞ where the mean is 0 but the
/// variance is not, 0 where both are).
pub fn relative_error(s: &Snapshot, i: usize) -> f32 {
    let m = luminance(s.mean[i]);
    let sd = luminance(s.variance[i]).max(0.0).sqrt();
    if sd == 0.0 {
        0.0
    } else if m > 0.0 {
        sd / m
    } else {
        f32::INFINITY
    }
}

/// RGBA8 pixels of one snapshot (or of two, split down the middle: the
/// left half from `left`, the right from `right`).
pub fn pixels(
    left: &Snapshot,
    right: Option<&Snapshot>,
    tone: &ToneMapping,
    overlay: Overlay,
) -> Vec<u8> {
    let (w, h) = (left.width as usize, left.height as usize);
    let mut out = Vec::with_capacity(w * h * 4);
    for y in 0..h {
        for x in 0..w {
            let s = match right {
                Some(r) if x >= w / 2 && r.width == left.width && r.height == left.height => r,
                _ => left,
            };
            let i = y * w + x;
            let rgb = match overlay {
                Overlay::Image => tone.display8(s.mean[i]),
                Overlay::RelativeError => viridis(relative_error(s, i) / REL_ERR_MAX),
            };
            let divider = right.is_some() && x == w / 2;
            out.extend_from_slice(&if divider { [255, 255, 255] } else { rgb });
            out.push(255);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snap(v: f32, var: f32) -> Snapshot {
        Snapshot {
            width: 4,
            height: 2,
            mean: vec![[v; 3]; 8],
            variance: vec![[var; 3]; 8],
            spp: 1,
            seconds: 1.0,
            samples: 8,
        }
    }

    #[test]
    fn split_screen_takes_each_half_from_its_session() {
        let (a, b) = (snap(0.0, 0.0), snap(1.0, 0.0));
        let p = pixels(&a, Some(&b), &ToneMapping::default(), Overlay::Image);
        assert_eq!(p[0], 0); // left: black
        assert_eq!(&p[4 * 2..4 * 2 + 3], &[255, 255, 255]); // the divider
        assert_eq!(p[4 * 3], 255); // right: white
    }

    #[test]
    fn relative_error_is_sd_over_mean_in_false_colour() {
        let s = snap(2.0, 0.04);
        assert!((relative_error(&s, 0) - 0.1).abs() < 1e-6);
        let p = pixels(&s, None, &ToneMapping::default(), Overlay::RelativeError);
        assert_eq!(&p[..3], &viridis(0.5));
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(7.0), [253, 231, 37]);
    }
}

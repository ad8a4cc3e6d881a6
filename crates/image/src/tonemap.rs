//! Display transforms: linear scene radiance → display-encoded sRGB in
//! [0, 1], for PNG files and the viewer. An exposure in stops scales the
//! radiance first; then one of three curves:
//!
//! | curve | what it does |
//! |---|---|
//! | `linear` | clamp to [0, 1], sRGB transfer function (what fogbank wrote before curves existed; exact for measurements) |
//! | `aces` | Narkowicz's fit of the ACES reference rendering + output transform (with his 0.6 pre-scale), then sRGB |
//! | `agx` | Sobotka's AgX base look through Wrensch's polynomial fit of its sigmoid: a gentle shoulder that desaturates highlights towards white instead of skewing their hue (Blender's default since 4.0); its output is already display-encoded |
//!
//! Non-finite input shows as black, so no NaN reaches a file.

use serde::{Deserialize, Serialize};

/// The tone curve (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ToneCurve {
    #[default]
    Linear,
    Aces,
    Agx,
}

impl ToneCurve {
    pub const NAMES: [&'static str; 3] = ["linear", "aces", "agx"];

    pub fn name(self) -> &'static str {
        match self {
            ToneCurve::Linear => "linear",
            ToneCurve::Aces => "aces",
            ToneCurve::Agx => "agx",
        }
    }

    /// The next curve in [`ToneCurve::NAMES`] order, wrapping around.
    pub fn next(self) -> ToneCurve {
        match self {
            ToneCurve::Linear => ToneCurve::Aces,
            ToneCurve::Aces => ToneCurve::Agx,
            ToneCurve::Agx => ToneCurve::Linear,
        }
    }

    pub fn parse(s: &str) -> Result<ToneCurve, String> {
        match s {
            "linear" => Ok(ToneCurve::Linear),
            "aces" => Ok(ToneCurve::Aces),
            "agx" => Ok(ToneCurve::Agx),
            _ => Err(format!(
                "unknown tone curve {s:?}; choose one of {}",
                ToneCurve::NAMES.join(", ")
            )),
        }
    }
}

/// Rec. 709 luminance of linear RGB (the weights every display-side
/// measure of fogbank uses: error overlays, automatic exposure).
#[inline]
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Exposure (stops) and curve: what turns a linear image into display
/// values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToneMapping {
    pub exposure: f32,
    pub curve: ToneCurve,
}

impl Default for ToneMapping {
    fn default() -> Self {
        ToneMapping {
            exposure: 0.0,
            curve: ToneCurve::Linear,
        }
    }
}

impl ToneMapping {
    /// Display-encoded sRGB in [0, 1] of one linear RGB value.
    pub fn display(&self, rgb: [f32; 3]) -> [f32; 3] {
        let k = self.exposure.exp2();
        let x = rgb.map(|c| if c.is_finite() { (c * k).max(0.0) } else { 0.0 });
        let x = if x.iter().all(|c| c.is_finite()) {
            x
        } else {
            [0.0; 3]
        };
        match self.curve {
            ToneCurve::Linear => x.map(|c| linear_to_srgb(c.min(1.0))),
            ToneCurve::Aces => x.map(|c| linear_to_srgb(aces_narkowicz(c))),
            ToneCurve::Agx => agx(x),
        }
    }

    /// 8-bit display values of one linear RGB value.
    pub fn display8(&self, rgb: [f32; 3]) -> [u8; 3] {
        self.display(rgb).map(|v| (v * 255.0 + 0.5) as u8)
    }
}

/// The sRGB decoding function (IEC 61966-2-1) of an encoded value in [0, 1].
pub fn srgb_to_linear(s: f32) -> f32 {
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB encoding function of a linear value, not clamped.
pub fn linear_to_srgb(l: f32) -> f32 {
    if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// Narkowicz 2016, "ACES Filmic Tone Mapping Curve", with the 0.6 scale
/// his post recommends so that 1.0 in maps near the reference's mid-range.
fn aces_narkowicz(x: f32) -> f32 {
    let x = 0.6 * x;
    let (a, b, c, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
    ((x * (a * x + b)) / (x * (c * x + d) + e)).clamp(0.0, 1.0)
}

/// AgX's inset matrix (linear Rec. 709 → AgX working space), rows.
const AGX_INSET: [[f32; 3]; 3] = [
    [0.842_479_06, 0.078_433_6, 0.079_223_745],
    [0.042_328_242, 0.878_468_6, 0.079_166_13],
    [0.042_375_655, 0.078_433_6, 0.879_143],
];
/// Its inverse, applied after the sigmoid (the "outset" of the base look).
const AGX_OUTSET: [[f32; 3]; 3] = [
    [1.196_879, -0.098_020_88, -0.099_029_74],
    [-0.052_896_85, 1.151_903_1, -0.098_961_18],
    [-0.052_971_635, -0.098_043_45, 1.151_073_7],
];
/// The log2 exposure window the sigmoid spans, relative to 0.18 grey.
const AGX_MIN_EV: f32 = -12.473_93;
const AGX_MAX_EV: f32 = 4.026_069;

fn mat3(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// AgX base look: inset, log2 encoding over [min EV, max EV], the sigmoid
/// (Wrensch's 6th-order fit), outset. Output is display-encoded.
fn agx(x: [f32; 3]) -> [f32; 3] {
    let v = mat3(&AGX_INSET, x).map(|c| {
        let ev = c.max(1e-10).log2().clamp(AGX_MIN_EV, AGX_MAX_EV);
        let t = (ev - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
        let (t2, t4) = (t * t, t * t * t * t);
        15.5 * t4 * t2 - 40.14 * t4 * t + 31.96 * t4 - 6.868 * t2 * t + 0.4298 * t2 + 0.1191 * t
            - 0.00232
    });
    mat3(&AGX_OUTSET, v).map(|c| c.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tm(curve: ToneCurve) -> ToneMapping {
        ToneMapping {
            exposure: 0.0,
            curve,
        }
    }

    #[test]
    fn curves_are_monotone_bounded_and_black_at_zero() {
        for curve in [ToneCurve::Linear, ToneCurve::Aces, ToneCurve::Agx] {
            let t = tm(curve);
            let black = t.display([0.0; 3]);
            assert!(black.iter().all(|&c| c < 0.01), "{curve:?} black {black:?}");
            let mut last = -1.0;
            for i in 0..200 {
                let v = 1e-3 * 1.06f32.powi(i);
                let d = t.display([v; 3])[1];
                assert!(
                    (0.0..=1.0).contains(&d) && d >= last - 1e-6,
                    "{curve:?} at {v}: {d}"
                );
                last = d;
            }
            // A very bright grey saturates to (nearly) white.
            assert!(t.display([1e4; 3]).iter().all(|&c| c > 0.95), "{curve:?}");
        }
    }

    #[test]
    fn mid_grey_maps_to_the_middle_and_exposure_is_a_scale() {
        // 0.18 grey: sRGB 0.46 linear; AgX places it near 0.5 of its range.
        let agx = tm(ToneCurve::Agx).display([0.18; 3])[0];
        assert!((0.4..0.6).contains(&agx), "{agx}");
        let lin = tm(ToneCurve::Linear).display([0.18; 3])[0];
        assert!((lin - 0.4613).abs() < 1e-3, "{lin}");
        let up = ToneMapping {
            exposure: 1.0,
            curve: ToneCurve::Aces,
        };
        assert_eq!(up.display([0.1; 3]), tm(ToneCurve::Aces).display([0.2; 3]));
    }

    #[test]
    fn non_finite_input_is_black() {
        for curve in [ToneCurve::Linear, ToneCurve::Aces, ToneCurve::Agx] {
            let d = tm(curve).display([f32::NAN, f32::INFINITY, 1.0]);
            assert_eq!(d, tm(curve).display([0.0, 0.0, 1.0]), "{curve:?}");
        }
    }
}

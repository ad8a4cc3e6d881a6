//! Blackbody emission colour: the Planck spectrum at temperature T,
//! normalised to peak 1 (as pbrt-v4's `BlackbodySpectrum`), projected to
//! linear sRGB through the CIE 1931 colour-matching functions.

use fogbank_math::Vec3;
use std::sync::OnceLock;

const H: f64 = 6.626_070_15e-34;
const C: f64 = 299_792_458.0;
const K_B: f64 = 1.380_649e-23;
/// Wien's displacement constant (m·K): the spectrum peaks at b / T.
const WIEN_B: f64 = 2.897_771_955e-3;

/// Planck's law: spectral radiance at wavelength `lambda` (m), temperature `t` (K).
pub fn planck(lambda: f64, t: f64) -> f64 {
    let l5 = lambda.powi(5);
    2.0 * H * C * C / (l5 * ((H * C / (lambda * K_B * t)).exp_m1()))
}

fn lobe(x: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let s = if x < mu { s1 } else { s2 };
    (-0.5 * ((x - mu) / s).powi(2)).exp()
}

/// CIE 1931 2° colour-matching functions, the multi-lobe fit of Wyman,
/// Sloan and Shirley (JCGT 2013), `nm` in nanometres.
pub fn cie_xyz(nm: f64) -> [f64; 3] {
    [
        1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7)
            - 0.065 * lobe(nm, 501.1, 20.4, 26.2),
        0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1),
        1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8),
    ]
}

/// Linear sRGB (D65) from CIE XYZ.
pub fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = xyz;
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

/// XYZ of the peak-normalised Planck spectrum, scaled so that a constant
/// spectrum of 1 has Y = 1.
pub fn blackbody_xyz(t: f64) -> [f64; 3] {
    let peak = planck(WIEN_B / t, t);
    let (mut xyz, mut y_white) = ([0.0; 3], 0.0);
    for nm in 360..=830 {
        let nm = nm as f64;
        let b = planck(nm * 1e-9, t) / peak;
        let c = cie_xyz(nm);
        for i in 0..3 {
            xyz[i] += b * c[i];
        }
        y_white += c[1];
    }
    xyz.map(|v| v / y_white)
}

const T_MIN: f32 = 100.0;
const T_STEP: f32 = 25.0;
const T_COUNT: usize = 1597; // up to 40,000 K

/// (first temperature, step, values) of the table behind [`blackbody_rgb`],
/// for GPU ports that interpolate it the same way.
pub fn blackbody_table() -> (f32, f32, &'static [Vec3]) {
    (T_MIN, T_STEP, table())
}

fn table() -> &'static [Vec3] {
    static TABLE: OnceLock<Vec<Vec3>> = OnceLock::new();
    TABLE.get_or_init(|| {
        (0..T_COUNT)
            .map(|i| {
                let rgb = xyz_to_srgb(blackbody_xyz((T_MIN + i as f32 * T_STEP) as f64));
                // Out-of-gamut reds at low temperature have a small negative
                // blue; emitted radiance must stay non-negative.
                Vec3::new(rgb[0] as f32, rgb[1] as f32, rgb[2] as f32).max(Vec3::ZERO)
            })
            .collect()
    })
}

/// Linear-sRGB radiance of the peak-normalised blackbody at `t` kelvin:
/// zero at or below 100 K (pbrt-v4's cutoff), interpolated from a 25 K
/// table, clamped at 40,000 K.
pub fn blackbody_rgb(t: f32) -> Vec3 {
    if t.is_nan() || t <= T_MIN {
        return Vec3::ZERO;
    }
    let x = ((t - T_MIN) / T_STEP).min((T_COUNT - 1) as f32);
    let i = (x as usize).min(T_COUNT - 2);
    let w = x - i as f32;
    let tab = table();
    tab[i] * (1.0 - w) + tab[i + 1] * w
}

#[cfg(test)]
mod blackbody_test {
    use super::*;

    fn chromaticity(t: f64) -> (f64, f64) {
        let [x, y, z] = blackbody_xyz(t);
        (x / (x + y + z), y / (x + y + z))
    }

    /// Planckian-locus chromaticities (CIE 1931) from the published tables;
    /// the analytic CMF fit is good to a few thousandths.
    #[test]
    fn planckian_locus_chromaticities() {
        for (t, x, y) in [
            (2000.0, 0.5267, 0.4133),
            (3000.0, 0.4369, 0.4041),
            (5000.0, 0.3451, 0.3516),
            (6500.0, 0.3135, 0.3237),
            (10000.0, 0.2807, 0.2884),
        ] {
            let (cx, cy) = chromaticity(t);
            assert!(
                (cx - x).abs() < 0.004 && (cy - y).abs() < 0.004,
                "{t} K: ({cx:.4}, {cy:.4}) vs ({x}, {y})"
            );
        }
    }

    #[test]
    fn warm_to_cold_and_table_matches_direct_evaluation() {
        let low = blackbody_rgb(1500.0);
        assert!(low.x > low.y && low.y > low.z, "{low}");
        let high = blackbody_rgb(15000.0);
        assert!(high.z > high.x, "{high}");
        assert_eq!(blackbody_rgb(100.0), Vec3::ZERO);
        assert_eq!(blackbody_rgb(f32::NAN), Vec3::ZERO);
        for t in [350.0f32, 1234.5, 6500.0, 27_000.0] {
            let direct = xyz_to_srgb(blackbody_xyz(t as f64));
            let tab = blackbody_rgb(t);
            for c in 0..3 {
                let d = direct[c].max(0.0) as f32;
                assert!(
                    (tab[c] - d).abs() <= 2e-2 * d + 1e-6,
                    "{t}: {tab} vs {direct:?}"
                );
            }
        }
        assert!(blackbody_rgb(1e9).is_finite());
    }
}

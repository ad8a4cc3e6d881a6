//! Spectra as linear sRGB, the way Mitsuba 3's RGB variants turn a
//! `<spectrum>` of wavelength:value pairs into a colour when they read a
//! scene (`spectrum_list_to_srgb` in Mitsuba's `spectrum.cpp`, called from
//! `Properties`): the piecewise-linear spectrum, sampled at 1000 points
//! over the CIE range [360, 830] nm (zero outside its own first and last
//! wavelength), weighted by the CIE 1931 2° colour-matching functions and,
//! for anything but emitted light, by the D65 illuminant, summed, scaled so
//! that a unit spectrum has luminance 1, and converted from XYZ to linear
//! Rec. 709 / sRGB. Reflectances are then clamped to [0, 1]; emitted and
//! unbounded quantities only to ≥ 0.
//!
//! A constant spectrum is its value in every channel, except on an emitter:
//! there Mitsuba's RGB variants use value · M_XYZ→sRGB · (1, 1, 1), the
//! (slightly purple) colour of an equal-energy spectrum under a D65 white
//! point, so that they agree with its spectral variants.

/// How a spectrum is used, which decides its weighting and clamping.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumUse {
    /// Emitted radiance, intensity or irradiance: no D65, clamped to ≥ 0.
    Emitter,
    /// A reflectance or other bounded quantity: D65-weighted, clamped to [0, 1].
    Bounded,
    /// An unbounded, non-emitted quantity (a conductor's η, a volume's
    /// values): D65-weighted, clamped to ≥ 0.
    Unbounded,
}

/// First and last wavelength of the CIE tables (nm), 5 nm apart.
pub const CIE_MIN: f64 = 360.0;
pub const CIE_MAX: f64 = 830.0;
const CIE_SAMPLES: usize = 95;
/// Scales the colour-matching functions so that a unit spectrum has Y = 1.
const CIE_Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;
/// Scales the D65 table so that it has Y = 1.
const CIE_D65_NORMALIZATION: f64 = 1.0 / 98.997_417_518_762_55;

/// CIE 1931 2° standard observer x̄, ȳ, z̄ at 360, 365, …, 830 nm.
#[rustfmt::skip]
const CIE_X: [f32; CIE_SAMPLES] = [
    0.000_129_9, 0.000_232_1, 0.000_414_9, 0.000_741_6, 0.001_368, 0.002_236, 0.004_243,
    0.007_65, 0.014_31, 0.023_19, 0.043_51, 0.077_63, 0.134_38, 0.214_77, 0.283_9, 0.328_5,
    0.348_28, 0.348_06, 0.336_2, 0.318_7, 0.290_8, 0.251_1, 0.195_36, 0.142_1, 0.095_64,
    0.057_950_01, 0.032_01, 0.014_7, 0.004_9, 0.002_4, 0.009_3, 0.029_1, 0.063_27, 0.109_6,
    0.165_5, 0.225_749_9, 0.290_4, 0.359_7, 0.433_449_9, 0.512_050_1, 0.594_5, 0.678_4,
    0.762_1, 0.842_5, 0.916_3, 0.978_6, 1.026_3, 1.056_7, 1.062_2, 1.045_6, 1.002_6, 0.938_4,
    0.854_449_9, 0.751_4, 0.642_4, 0.541_9, 0.447_9, 0.360_8, 0.283_5, 0.218_7, 0.164_9,
    0.121_2, 0.087_4, 0.063_6, 0.046_77, 0.032_9, 0.022_7, 0.015_84, 0.011_359_16,
    0.008_110_916, 0.005_790_346, 0.004_109_457, 0.002_899_327, 0.002_049_19, 0.001_439_971,
    0.000_999_949_3, 0.000_690_078_6, 0.000_476_021_3, 0.000_332_301_1, 0.000_234_826_1,
    0.000_166_150_5, 0.000_117_413, 0.000_083_075_27, 0.000_058_706_52, 0.000_041_509_94,
    0.000_029_353_26, 0.000_020_673_83, 0.000_014_559_77, 0.000_010_253_98, 0.000_007_221_456,
    0.000_005_085_868, 0.000_003_581_652, 0.000_002_522_525, 0.000_001_776_509,
    0.000_001_251_141,
];

#[rustfmt::skip]
const CIE_Y: [f32; CIE_SAMPLES] = [
    0.000_003_917, 0.000_006_965, 0.000_012_39, 0.000_022_02, 0.000_039, 0.000_064, 0.000_12,
    0.000_217, 0.000_396, 0.000_64, 0.001_21, 0.002_18, 0.004, 0.007_3, 0.011_6, 0.016_84,
    0.023, 0.029_8, 0.038, 0.048, 0.06, 0.073_9, 0.090_98, 0.112_6, 0.139_02, 0.169_3,
    0.208_02, 0.258_6, 0.323, 0.407_3, 0.503, 0.608_2, 0.71, 0.793_2, 0.862, 0.914_850_1,
    0.954, 0.980_3, 0.994_950_1, 1.0, 0.995, 0.978_6, 0.952, 0.915_4, 0.87, 0.816_3, 0.757,
    0.694_9, 0.631, 0.566_8, 0.503, 0.441_2, 0.381, 0.321, 0.265, 0.217, 0.175, 0.138_2,
    0.107, 0.081_6, 0.061, 0.044_58, 0.032, 0.023_2, 0.017, 0.011_92, 0.008_21, 0.005_723,
    0.004_102, 0.002_929, 0.002_091, 0.001_484, 0.001_047, 0.000_74, 0.000_52, 0.000_361_1,
    0.000_249_2, 0.000_171_9, 0.000_12, 0.000_084_8, 0.000_06, 0.000_042_4, 0.000_03,
    0.000_021_2, 0.000_014_99, 0.000_010_6, 0.000_007_465_7, 0.000_005_257_8,
    0.000_003_702_9, 0.000_002_607_8, 0.000_001_836_6, 0.000_001_293_4, 0.000_000_910_93,
    0.000_000_641_53, 0.000_000_451_81,
];

#[rustfmt::skip]
const CIE_Z: [f32; CIE_SAMPLES] = [
    0.000_606_1, 0.001_086, 0.001_946, 0.003_486, 0.006_450_001, 0.010_549_99, 0.020_050_01,
    0.036_21, 0.067_850_01, 0.110_2, 0.207_4, 0.371_3, 0.645_6, 1.039_050_1, 1.385_6,
    1.622_96, 1.747_06, 1.782_6, 1.772_11, 1.744_1, 1.669_2, 1.528_1, 1.287_64, 1.041_9,
    0.812_950_1, 0.616_2, 0.465_18, 0.353_3, 0.272, 0.212_3, 0.158_2, 0.111_7, 0.078_249_99,
    0.057_250_01, 0.042_16, 0.029_84, 0.020_3, 0.013_4, 0.008_749_999, 0.005_749_999, 0.003_9,
    0.002_749_999, 0.002_1, 0.001_8, 0.001_650_001, 0.001_4, 0.001_1, 0.001, 0.000_8, 0.000_6,
    0.000_34, 0.000_24, 0.000_19, 0.000_1, 0.000_049_999_99, 0.000_03, 0.000_02, 0.000_01,
    0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    0.0,
];

/// CIE standard illuminant D65, relative spectral power at 360, 365, …, 830 nm.
#[rustfmt::skip]
const D65: [f32; CIE_SAMPLES] = [
    46.6383, 49.3637, 52.0891, 51.0323, 49.9755, 52.3118, 54.6482, 68.7015, 82.7549, 87.1204,
    91.486, 92.4589, 93.4318, 90.057, 86.6823, 95.7736, 104.865, 110.936, 117.008, 117.41,
    117.812, 116.336, 114.861, 115.392, 115.923, 112.367, 108.811, 109.082, 109.354, 108.578,
    107.802, 106.296, 104.79, 106.239, 107.689, 106.047, 104.405, 104.225, 104.046, 102.023,
    100.0, 98.1671, 96.3342, 96.0611, 95.788, 92.2368, 88.6856, 89.3459, 90.0062, 89.8026,
    89.5991, 88.6489, 87.6987, 85.4936, 83.2886, 83.4939, 83.6992, 81.863, 80.0268, 80.1207,
    80.2146, 81.2462, 82.2778, 80.281, 78.2842, 74.0027, 69.7213, 70.6652, 71.6091, 72.979,
    74.349, 67.9765, 61.604, 65.7448, 69.8856, 72.4863, 75.087, 69.3398, 63.5927, 55.0054,
    46.4182, 56.6118, 66.8054, 65.0941, 63.3828, 63.8434, 64.304, 61.8779, 59.4519, 55.7054,
    51.959, 54.6998, 57.4406, 58.8765, 60.3125,
];

/// XYZ → linear Rec. 709 / sRGB (D65 white), the matrix Mitsuba uses.
#[rustfmt::skip]
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.240_479, -1.537_15, -0.498_535],
    [-0.969_256, 1.875_991, 0.041_556],
    [0.055_648, -0.204_043, 1.057_311],
];

/// Linear interpolation in a table at 360, 365, …, 830 nm.
fn table(t: &[f32; CIE_SAMPLES], nm: f64) -> f64 {
    let x = (nm - CIE_MIN) * ((CIE_SAMPLES - 1) as f64 / (CIE_MAX - CIE_MIN));
    let i0 = (x.max(0.0) as usize).min(CIE_SAMPLES - 2);
    let w1 = x - i0 as f64;
    (1.0 - w1) * t[i0] as f64 + w1 * t[i0 + 1] as f64
}

/// The colour-matching functions (x̄, ȳ, z̄) at `nm`, 0 outside [360, 830].
pub fn cie1931_xyz(nm: f64) -> [f64; 3] {
    if !(CIE_MIN..=CIE_MAX).contains(&nm) {
        return [0.0; 3];
    }
    [table(&CIE_X, nm), table(&CIE_Y, nm), table(&CIE_Z, nm)]
}

/// D65's relative power at `nm`, normalised to luminance 1.
pub fn cie_d65(nm: f64) -> f64 {
    if !(CIE_MIN..=CIE_MAX).contains(&nm) {
        return 0.0;
    }
    table(&D65, nm) * CIE_D65_NORMALIZATION
}

pub fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    XYZ_TO_SRGB.map(|row| row[0] * xyz[0] + row[1] * xyz[1] + row[2] * xyz[2])
}

/// The linear sRGB of the piecewise-linear spectrum through
/// (`wavelengths[i]`, `values[i]`) (nm, ascending, at least two), used as
/// `usage` says. Errors name what is wrong with the lists.
pub fn spectrum_to_srgb(
    wavelengths: &[f64],
    values: &[f64],
    usage: SpectrumUse,
) -> Result<[f64; 3], String> {
    if wavelengths.len() != values.len() || wavelengths.len() < 2 {
        return Err(format!(
            "a spectrum needs two or more wavelength:value pairs (got {})",
            wavelengths.len()
        ));
    }
    if wavelengths
        .windows(2)
        .any(|w| w[0].partial_cmp(&w[1]) != Some(std::cmp::Ordering::Less))
    {
        return Err("the wavelengths of a spectrum must increase".into());
    }
    const STEPS: usize = 1000;
    let (first, last) = (wavelengths[0], wavelengths[wavelengths.len() - 1]);
    let mut xyz = [0.0f64; 3];
    for i in 0..STEPS {
        let nm = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        if nm < first || nm > last {
            continue;
        }
        // The last interval whose start is at or below nm.
        let k = wavelengths
            .partition_point(|&w| w <= nm)
            .saturating_sub(1)
            .min(wavelengths.len() - 2);
        let (w0, w1) = (wavelengths[k], wavelengths[k + 1]);
        let v = ((nm - w1) * values[k] + (w0 - nm) * values[k + 1]) / (w0 - w1);
        let weight = if usage == SpectrumUse::Emitter {
            1.0
        } else {
            cie_d65(nm)
        };
        let cmf = cie1931_xyz(nm);
        for c in 0..3 {
            xyz[c] += cmf[c] * v * weight;
        }
    }
    let scale = (CIE_MAX - CIE_MIN) * CIE_Y_NORMALIZATION / STEPS as f64;
    Ok(clamp(xyz_to_srgb(xyz.map(|x| x * scale)), usage))
}

/// The linear sRGB of the constant spectrum `value`.
pub fn constant_spectrum_to_srgb(value: f64, usage: SpectrumUse) -> [f64; 3] {
    match usage {
        SpectrumUse::Emitter => xyz_to_srgb([value; 3]),
        _ => [value; 3],
    }
}

fn clamp(rgb: [f64; 3], usage: SpectrumUse) -> [f64; 3] {
    match usage {
        SpectrumUse::Bounded if rgb.iter().any(|&c| !(0.0..=1.0).contains(&c)) => {
            rgb.map(|c| c.clamp(0.0, 1.0))
        }
        _ => rgb.map(|c| c.max(0.0)),
    }
}

#[cfg(test)]
mod spectrum_test {
    use super::*;

    /// A unit spectrum over the whole range has luminance 1 (the
    /// normalisation's purpose), and under D65 it is white.
    #[test]
    fn unit_spectra_are_normalised() {
        let e = spectrum_to_srgb(&[CIE_MIN, CIE_MAX], &[1.0, 1.0], SpectrumUse::Emitter).unwrap();
        let y = 0.212_671 * e[0] + 0.715_160 * e[1] + 0.072_169 * e[2];
        assert!((y - 1.0).abs() < 2e-3, "{e:?}");
        let w = spectrum_to_srgb(&[CIE_MIN, CIE_MAX], &[1.0, 1.0], SpectrumUse::Unbounded).unwrap();
        for c in w {
            assert!((c - 1.0).abs() < 3e-3, "{w:?}");
        }
    }

    #[test]
    fn malformed_lists_are_errors() {
        assert!(spectrum_to_srgb(&[500.0], &[1.0], SpectrumUse::Bounded).is_err());
        assert!(spectrum_to_srgb(&[600.0, 500.0], &[1.0, 1.0], SpectrumUse::Bounded).is_err());
        assert!(spectrum_to_srgb(&[500.0, 600.0], &[1.0], SpectrumUse::Bounded).is_err());
    }
}

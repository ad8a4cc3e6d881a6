//! FLIP, NVIDIA's perceptual difference evaluator for rendered images:
//! LDR-FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for
//! Alternating Images", HPG) and HDR-FLIP (Andersson et al. 2021,
//! "Visualizing Errors in Rendered High Dynamic Range Images", EG short).
//!
//! Written from the papers, with the constants and numerical choices of the
//! authors' reference implementation (the `flip-evaluator` package), which
//! it matches to ≈1e-6 in mean FLIP (`tools/check_flip.py` prints the
//! comparison). Arithmetic is f32 like the reference's, so that the two
//! agree on the thresholded parts of the pipeline (clamps, the colour
//! difference's two-segment remap).

use super::flip_colour::{
    hunt, hyab, rgb_to_xyz, xyz_to_lab, xyz_to_rgb, xyz_to_ycxcz, ycxcz_to_xyz, C3,
};
use super::pixels::check_same_size;
use crate::image_io::Image;
use rayon::prelude::*;
use serde::Serialize;

/// Pixels per degree of visual angle for an observer at `distance` metres
/// from a monitor `monitor_width` metres wide showing `resolution_x` pixels
/// across (small-angle approximation, as FLIP defines it).
pub fn pixels_per_degree(distance: f32, resolution_x: f32, monitor_width: f32) -> f32 {
    distance * (resolution_x / monitor_width) * (std::f32::consts::PI / 180.0)
}

/// FLIP's default viewing condition: 0.7 m from a 0.7 m wide 4K monitor
/// (3840 px), ≈ 67.0206 pixels per degree.
pub fn default_ppd() -> f32 {
    pixels_per_degree(0.7, 3840.0, 0.7)
}

/// Which FLIP variant to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum FlipMode {
    /// LDR-FLIP when both images are sRGB PNGs (`is_srgb8`), else HDR-FLIP.
    Auto,
    /// LDR-FLIP on the linear values clamped to [0, 1].
    Ldr,
    /// HDR-FLIP.
    Hdr,
}

/// Tone mapper of HDR-FLIP (Andersson et al. 2021, Sec. 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Tonemapper {
    /// Narkowicz's fit of the ACES filmic curve, with the reference's 0.6
    /// pre-exposure cancelled (the default).
    Aces,
    /// Hable's Uncharted 2 curve as a rational fit.
    Hable,
    /// Reinhard, c/(1 + L) with the pixel's luminance L.
    Reinhard,
}

impl Tonemapper {
    /// Coefficients (a, b, c, d, e, f) of the per-channel rational curve
    /// (a x² + b x + c) / (d x² + e x + f); the reference uses the Reinhard
    /// row only to place the exposure range.
    fn coefficients(self) -> [f32; 6] {
        match self {
            Tonemapper::Reinhard => [0.0, 1.0, 0.0, 0.0, 1.0, 1.0],
            Tonemapper::Aces => [
                0.6 * 0.6 * 2.51,
                0.6 * 0.03,
                0.0,
                0.6 * 0.6 * 2.43,
                0.6 * 0.59,
                0.14,
            ],
            Tonemapper::Hable => [0.231683, 0.013791, 0.0, 0.18, 0.3, 0.018],
        }
    }

    fn apply(self, c: C3) -> C3 {
        match self {
            Tonemapper::Reinhard => {
                let k = 1.0 / (1.0 + luminance(c));
                c.map(|x| x * k)
            }
            _ => {
                let t = self.coefficients();
                c.map(|x| (x * x * t[0] + x * t[1] + t[2]) / (x * x * t[3] + x * t[4] + t[5]))
            }
        }
    }
}

/// Settings of [`flip_with`]; `Default` is the reference's defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct FlipOptions {
    pub mode: FlipMode,
    /// Pixels per degree; default [`default_ppd`].
    pub ppd: f32,
    pub tonemapper: Tonemapper,
    /// HDR-FLIP exposure range and count (in stops); computed from the
    /// reference when `None` (Andersson et al. 2021, Sec. 4).
    pub start_exposure: Option<f32>,
    pub stop_exposure: Option<f32>,
    pub num_exposures: Option<usize>,
}

impl Default for FlipOptions {
    fn default() -> Self {
        FlipOptions {
            mode: FlipMode::Auto,
            ppd: default_ppd(),
            tonemapper: Tonemapper::Aces,
            start_exposure: None,
            stop_exposure: None,
            num_exposures: None,
        }
    }
}

/// HDR-FLIP's exposure range as used.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Exposures {
    pub start: f32,
    pub stop: f32,
    pub count: usize,
}

/// Outcome of [`flip`].
#[derive(Clone, Debug, Serialize)]
pub struct FlipResult {
    /// Mean of the error map, in [0, 1].
    pub mean: f64,
    /// Per-pixel FLIP error in [0, 1], row-major.
    #[serde(skip)]
    pub map: Vec<f32>,
    /// True when HDR-FLIP ran.
    pub hdr: bool,
    /// HDR-FLIP's exposures (None for LDR-FLIP).
    pub exposures: Option<Exposures>,
    pub ppd: f32,
}

/// FLIP with the reference's defaults (67.02 PPD, ACES, automatic
/// exposures): LDR-FLIP when both images are sRGB PNGs, HDR-FLIP otherwise.
/// See [`flip_with`].
pub fn flip(reference: &Image, test: &Image) -> Result<FlipResult, String> {
    flip_with(reference, test, &FlipOptions::default())
}

/// FLIP error map and its mean.
///
/// LDR-FLIP (Andersson et al. 2020): both images go to YCxCz, are filtered
/// with the contrast sensitivity functions (Sec. 3.1: one Gaussian each for
/// achromatic and red-green, a sum of two for blue-yellow, scaled by PPD),
/// then compared in CIELab with the Hunt adjustment and the HyAB distance,
/// compressed (exponent 0.7) and remapped to [0, 1] (Sec. 3.2, Eq. 2–4);
/// edges and points found with first and second derivatives of a Gaussian
/// on the unfiltered luminance (Sec. 3.3) give the feature difference ΔF,
/// and the error is ΔE^(1 − ΔF) (Eq. 5).
///
/// HDR-FLIP (Andersson et al. 2021): LDR-FLIP between tone-mapped copies at
/// exposures spread evenly over [c_start, c_stop], keeping each pixel's
/// maximum. The range comes from the reference's luminance: the exposures at
/// which the tone curve maps its maximum and its median to 0.85.
pub fn flip_with(
    reference: &Image,
    test: &Image,
    options: &FlipOptions,
) -> Result<FlipResult, String> {
    check_same_size(reference, test)?;
    if !(options.ppd > 0.0 && options.ppd.is_finite()) {
        return Err(format!(
            "pixels per degree must be positive, got {}",
            options.ppd
        ));
    }
    let hdr = match options.mode {
        FlipMode::Auto => !(reference.is_srgb8 && test.is_srgb8),
        FlipMode::Ldr => false,
        FlipMode::Hdr => true,
    };
    let (w, h) = (reference.width, reference.height);
    let clamp01 = |img: &Image| -> Vec<C3> {
        img.rgb
            .iter()
            .map(|c| c.map(|x| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }))
            .collect()
    };
    if !hdr {
        let map = ldr_flip(&clamp01(reference), &clamp01(test), w, h, options.ppd);
        return Ok(FlipResult {
            mean: mean(&map),
            map,
            hdr: false,
            exposures: None,
            ppd: options.ppd,
        });
    }

    hdr_flip(reference, test, options)
}

/// HDR-FLIP (Andersson et al. 2021): the maximum of LDR-FLIP over tone-
/// mapped copies at the exposures of `options` (or the reference's range).
fn hdr_flip(reference: &Image, test: &Image, options: &FlipOptions) -> Result<FlipResult, String> {
    let (w, h) = (reference.width, reference.height);
    // Negative and NaN values are not radiance; clamp them to 0.
    let sanitize = |img: &Image| -> Vec<C3> {
        img.rgb
            .iter()
            .map(|c| c.map(|x| if x > 0.0 { x } else { 0.0 }))
            .collect()
    };
    let (r, t) = (sanitize(reference), sanitize(test));
    let (auto_start, auto_stop) = exposure_range(&r, options.tonemapper);
    let start = options.start_exposure.unwrap_or(auto_start);
    let stop = options.stop_exposure.unwrap_or(auto_stop);
    if !(start.is_finite() && stop.is_finite()) || start > stop {
        return Err(format!(
            "invalid HDR-FLIP exposure range [{start}, {stop}] (start must not exceed stop)"
        ));
    }
    let count = options
        .num_exposures
        .unwrap_or_else(|| (stop - start).ceil().max(2.0) as usize);
    if count < 1 {
        return Err("HDR-FLIP needs at least one exposure".to_string());
    }
    let step = if count > 1 {
        (stop - start) / (count - 1) as f32
    } else {
        0.0
    };
    let mut map = vec![0f32; w * h];
    for i in 0..count {
        let exposure = start + i as f32 * step;
        let scale = 2f32.powf(exposure);
        let ldr = |img: &[C3]| -> Vec<C3> {
            img.iter()
                .map(|&c| {
                    options
                        .tonemapper
                        .apply(c.map(|x| x * scale))
                        .map(|x| x.clamp(0.0, 1.0))
                })
                .collect()
        };
        let m = ldr_flip(&ldr(&r), &ldr(&t), w, h, options.ppd);
        for (a, b) in map.iter_mut().zip(&m) {
            if *b > *a {
                *a = *b;
            }
        }
    }
    Ok(FlipResult {
        mean: mean(&map),
        map,
        hdr: true,
        exposures: Some(Exposures { start, stop, count }),
        ppd: options.ppd,
    })
}

fn mean(map: &[f32]) -> f64 {
    map.iter().map(|&x| x as f64).sum::<f64>() / map.len() as f64
}

/// Rec. 709 luminance of linear RGB.
fn luminance(c: C3) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// HDR-FLIP's automatic exposure range (Andersson et al. 2021, Sec. 4):
/// c_start maps the reference's largest luminance, c_stop its median, to the
/// point where the tone curve reaches 0.85. As in the reference, the median
/// is the element of rank ⌊n/2⌋. A black image or a black median (where the
/// reference's range would be infinite) falls back to the smallest positive
/// luminance, so that the range stays finite.
fn exposure_range(reference: &[C3], tm: Tonemapper) -> (f32, f32) {
    // x with tm(x) = 0.85: the larger root of (a − t d) x² + (b − t e) x + (c − t f).
    let k = tm.coefficients();
    let target = 0.85f32;
    let (a, b, c) = (
        k[0] - target * k[3],
        k[1] - target * k[4],
        k[2] - target * k[5],
    );
    let x_max = if a == 0.0 {
        -c / b
    } else {
        let d1 = -0.5 * (b / a);
        d1 + (d1 * d1 - c / a).sqrt()
    };
    let mut lum: Vec<f32> = reference.iter().map(|&p| luminance(p)).collect();
    let y_max = lum.iter().copied().fold(0f32, f32::max);
    let y_min_pos = lum
        .iter()
        .copied()
        .filter(|&y| y > 0.0)
        .fold(f32::INFINITY, f32::min);
    let mid = lum.len() / 2;
    let (_, &mut y_median, _) = lum.select_nth_unstable_by(mid, |p, q| p.total_cmp(q));
    if y_max <= 0.0 {
        return (0.0, 0.0);
    }
    let y_median = if y_median > 0.0 { y_median } else { y_min_pos };
    ((x_max / y_max).log2(), (x_max / y_median).log2())
}

// --- Constants of Andersson et al. 2020 -----------------------------------

/// Exponent q_c compressing colour differences.
const QC: f32 = 0.7;
/// Fraction p_c of the maximum colour difference where the remap bends.
const PC: f32 = 0.4;
/// Error p_t assigned at that bend.
const PT: f32 = 0.95;
/// Feature filter width w in degrees.
const GW: f32 = 0.082;
/// Exponent q_f of the feature difference.
const QF: f32 = 0.5;

/// CSF Gaussians g(x) = a·sqrt(π/b)·exp(−π²x²/b) per opponent channel
/// (Andersson et al. 2020, Eq. 1, Table 1): (a1, b1, a2, b2) for Y, Cx, Cz;
/// only blue-yellow (Cz) has a second Gaussian.
const CSF: [[f32; 4]; 3] = [
    [1.0, 0.0047, 0.0, 1e-5],
    [1.0, 0.0053, 0.0, 1e-5],
    [34.1, 0.04, 13.5, 0.025],
];

/// The largest possible colour difference (between pure green and pure blue,
/// after Hunt adjustment), compressed by q_c.
fn max_color_difference() -> f32 {
    let lab = |c: C3| hunt(xyz_to_lab(rgb_to_xyz(c)));
    hyab(lab([0.0, 1.0, 0.0]), lab([0.0, 0.0, 1.0])).powf(QC)
}

// --- Filters ---------------------------------------------------------------

/// 1D kernels for the CSF filtering, built so that separable passes give the
/// 2D sums of Gaussians: Y and Cx use one normalised Gaussian each; Cz's 2D
/// kernel G1(x)G1(y) + G2(x)G2(y) is filtered as two separable passes whose
/// 1D factors sqrt(a·sqrt(π/b))·exp(−π²x²/b) share one normalisation making
/// the 2D kernel sum to 1.
struct SpatialKernels {
    y: Vec<f32>,
    cx: Vec<f32>,
    cz1: Vec<f32>,
    cz2: Vec<f32>,
}

fn spatial_kernels(ppd: f32) -> SpatialKernels {
    let pi = std::f32::consts::PI;
    let pi2 = pi * pi;
    // Radius covers 3 standard deviations of the widest Gaussian; b is the
    // scale in the exp(−π²x²/b) form, whose σ is sqrt(b/(2π²)) degrees.
    let b_max = CSF.iter().flat_map(|k| [k[1], k[3]]).fold(0f32, f32::max);
    let radius = (3.0 * (b_max / (2.0 * pi2)).sqrt() * ppd).ceil() as i64;
    let xs: Vec<f32> = (-radius..=radius).map(|i| i as f32 / ppd).collect();
    let gauss = |a: f32, b: f32, x: f32| a * (pi / b).sqrt() * (-pi2 * x * x / b).exp();
    let gauss_sqrt =
        |a: f32, b: f32, x: f32| (a * (pi / b).sqrt()).sqrt() * (-pi2 * x * x / b).exp();
    let normalised = |v: Vec<f32>| {
        let s: f32 = v.iter().sum();
        v.into_iter().map(|x| x / s).collect::<Vec<f32>>()
    };
    let y = normalised(xs.iter().map(|&x| gauss(CSF[0][0], CSF[0][1], x)).collect());
    let cx = normalised(xs.iter().map(|&x| gauss(CSF[1][0], CSF[1][1], x)).collect());
    let cz1: Vec<f32> = xs
        .iter()
        .map(|&x| gauss_sqrt(CSF[2][0], CSF[2][1], x))
        .collect();
    let cz2: Vec<f32> = xs
        .iter()
        .map(|&x| gauss_sqrt(CSF[2][2], CSF[2][3], x))
        .collect();
    let (s1, s2): (f32, f32) = (cz1.iter().sum(), cz2.iter().sum());
    let k = 1.0 / (s1 * s1 + s2 * s2).sqrt();
    SpatialKernels {
        y,
        cx,
        cz1: cz1.into_iter().map(|x| x * k).collect(),
        cz2: cz2.into_iter().map(|x| x * k).collect(),
    }
}

/// Edge and point detectors (Andersson et al. 2020, Sec. 3.3): a Gaussian of
/// σ = w/2 degrees and its first and second derivatives, radius 3σ. The
/// Gaussian sums to 1; the positive and negative lobes of each derivative
/// sum to +1 and −1, so a flat region responds with 0 and a unit step with
/// a fixed magnitude.
struct FeatureKernels {
    g: Vec<f32>,
    dg: Vec<f32>,
    ddg: Vec<f32>,
}

fn feature_kernels(ppd: f32) -> FeatureKernels {
    let sd = 0.5 * GW * ppd;
    let radius = (3.0 * sd).ceil() as i64;
    let mut g = Vec::new();
    let mut dg = Vec::new();
    let mut ddg = Vec::new();
    for i in -radius..=radius {
        let x = i as f32;
        let v = (-(x * x) / (2.0 * sd * sd)).exp();
        g.push(v);
        dg.push(-x * v);
        ddg.push((x * x / (sd * sd) - 1.0) * v);
    }
    let sum_g: f32 = g.iter().sum();
    let lobes = |v: &[f32]| {
        let pos: f32 = v.iter().filter(|&&x| x > 0.0).sum();
        let neg: f32 = -v.iter().filter(|&&x| x <= 0.0).sum::<f32>();
        v.iter()
            .map(|&x| if x > 0.0 { x / pos } else { x / neg })
            .collect::<Vec<f32>>()
    };
    FeatureKernels {
        g: g.iter().map(|x| x / sum_g).collect(),
        dg: lobes(&dg),
        ddg: lobes(&ddg),
    }
}

/// Horizontal convolution with clamp-to-edge borders.
fn conv_h(src: &[f32], w: usize, kernel: &[f32]) -> Vec<f32> {
    let r = (kernel.len() / 2) as isize;
    let mut out = vec![0f32; src.len()];
    out.par_chunks_mut(w)
        .zip(src.par_chunks(w))
        .for_each(|(o, row)| {
            for (x, ov) in o.iter_mut().enumerate() {
                let mut s = 0f32;
                for (j, &k) in kernel.iter().enumerate() {
                    let xx = (x as isize + j as isize - r).clamp(0, w as isize - 1) as usize;
                    s += k * row[xx];
                }
                *ov = s;
            }
        });
    out
}

/// Vertical convolution with clamp-to-edge borders.
fn conv_v(src: &[f32], w: usize, h: usize, kernel: &[f32]) -> Vec<f32> {
    let r = (kernel.len() / 2) as isize;
    let mut out = vec![0f32; src.len()];
    out.par_chunks_mut(w).enumerate().for_each(|(y, o)| {
        for (j, &k) in kernel.iter().enumerate() {
            let yy = (y as isize + j as isize - r).clamp(0, h as isize - 1) as usize;
            let row = &src[yy * w..(yy + 1) * w];
            for (ov, &v) in o.iter_mut().zip(row) {
                *ov += k * v;
            }
        }
    });
    out
}

fn plane(img: &[C3], c: usize) -> Vec<f32> {
    img.iter().map(|p| p[c]).collect()
}

/// LDR-FLIP of two linear RGB images with values in [0, 1].
fn ldr_flip(reference: &[C3], test: &[C3], w: usize, h: usize, ppd: f32) -> Vec<f32> {
    let to_ycxcz =
        |img: &[C3]| -> Vec<C3> { img.iter().map(|&c| xyz_to_ycxcz(rgb_to_xyz(c))).collect() };
    let (r, t) = (to_ycxcz(reference), to_ycxcz(test));

    // Colour pipeline (Sec. 3.1–3.2): CSF-filtered opponent channels.
    let sk = spatial_kernels(ppd);
    let filtered = |img: &[C3]| -> Vec<C3> {
        let sep = |p: &[f32], k: &[f32]| conv_v(&conv_h(p, w, k), w, h, k);
        let cz = plane(img, 2);
        let y = sep(&plane(img, 0), &sk.y);
        let cx = sep(&plane(img, 1), &sk.cx);
        let cz1 = sep(&cz, &sk.cz1);
        let cz2 = sep(&cz, &sk.cz2);
        (0..w * h).map(|i| [y[i], cx[i], cz1[i] + cz2[i]]).collect()
    };
    let (rf, tf) = (filtered(&r), filtered(&t));
    let cmax = max_color_difference();
    let pccmax = PC * cmax;
    // Filtered colours may leave the gamut; clamp in linear RGB before Lab.
    let to_lab = |c: C3| {
        let rgb = xyz_to_rgb(ycxcz_to_xyz(c)).map(|x| x.clamp(0.0, 1.0));
        hunt(xyz_to_lab(rgb_to_xyz(rgb)))
    };
    let color: Vec<f32> = rf
        .par_iter()
        .zip(tf.par_iter())
        .map(|(&a, &b)| {
            let d = hyab(to_lab(a), to_lab(b)).powf(QC);
            // Eq. 4: [0, p_c·c_max] → [0, p_t], the rest → (p_t, 1].
            if d < pccmax {
                d * (PT / pccmax)
            } else {
                PT + ((d - pccmax) / (cmax - pccmax)) * (1.0 - PT)
            }
        })
        .collect();

    // Feature pipeline (Sec. 3.3) on the unfiltered achromatic channel
    // normalised to [0, 1].
    let fk = feature_kernels(ppd);
    let features = |img: &[C3]| -> (Vec<f32>, Vec<f32>) {
        let gray: Vec<f32> = img.iter().map(|c| (c[0] + 16.0) / 116.0).collect();
        let gx = conv_h(&gray, w, &fk.g);
        let dx = conv_v(&conv_h(&gray, w, &fk.dg), w, h, &fk.g);
        let ddx = conv_v(&conv_h(&gray, w, &fk.ddg), w, h, &fk.g);
        let dy = conv_v(&gx, w, h, &fk.dg);
        let ddy = conv_v(&gx, w, h, &fk.ddg);
        let edge = (0..w * h).map(|i| dx[i].hypot(dy[i])).collect();
        let point = (0..w * h).map(|i| ddx[i].hypot(ddy[i])).collect();
        (edge, point)
    };
    let ((re, rp), (te, tp)) = (features(&r), features(&t));
    let inv_sqrt2 = std::f32::consts::FRAC_1_SQRT_2;
    (0..w * h)
        .into_par_iter()
        .map(|i| {
            let df = (inv_sqrt2 * (re[i] - te[i]).abs().max((rp[i] - tp[i]).abs())).powf(QF);
            // Eq. 5: features sharpen the colour error.
            color[i].powf(1.0 - df)
        })
        .collect()
}

//! Peters 2025 Fig. 13: the bias of Eq. 10 (biased MIS that merges weight and
//! transmittance estimation) with the naive weight g(X̄) (`mis_naive`, one
//! optical-depth estimate of 2N lookups) against jackknife weights
//! Re g(X̄ + iS) (`mis_jackknife_biased`, Eq. 12), in a high-spp inset of
//! the fig12 scene around the warm point light.
//!
//! A difference of two renders cannot resolve these biases at N = 10 in
//! minutes (fig12: both within 1.6 SE of zero at 512 spp). Instead every
//! pixel sample is evaluated by [`PointMis::eq10_weight_errors`]: the light,
//! the two distances and one L̃_s per distance are drawn as the Eq. 10
//! strategies draw them, the exact weight g(τ) comes from regular tracking
//! (nearest filter), and each estimated weight g̃ from its own optical-depth
//! estimates. Then
//!
//! * Σ_j g(τ(t_j)) L̃_s(t_j) is an unbiased estimate of the radiance (Eq. 10
//!   with exact weights is the balance heuristic): the reference;
//! * Σ_j (g̃(t_j) − g(τ(t_j))) L̃_s(t_j) has expectation exactly equal to the
//!   bias of the integrator's strategy (g̃ and L̃_s use independent random
//!   numbers, as in the integrator), but only the weight error's variance:
//!   the distance-sampling noise that dominates a render is common to the
//!   reference and the variant (common random numbers) and cancels;
//! * the naive and jackknife errors share the same distances and L̃_s too, so
//!   their difference resolves the ordering with a paired standard error.
//!
//! One pass evaluates N = 1, 2, 4, 10 on the same samples. As a check that
//! the shortcut measures the real integrator, `mis_naive` and
//! `mis_jackknife_biased` are also rendered by `point_mis` itself at N = 1,
//! 2 and 10 and compared with the exact-weight reference (plain, noisier
//! difference of means).

use super::fig12::rgb_mean_and_var;
use crate::harness::protocol::render_at;
use crate::harness::timing::clocked;
use crate::harness::Writer;
use fogbank_eval::image_io::linear_to_srgb;
use fogbank_math::{SampleKey, Vec3};
use fogbank_render::integrators::point_mis::PointMis;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, Scene};
use rayon::prelude::*;
use std::path::Path;

/// N of the optical-depth estimates behind the weights (the paper: 10).
pub const MIS_SAMPLES: [u32; 4] = [1, 2, 4, 10];
/// Pixel samples of the shortcut pass (`--trials` overrides).
pub const DEFAULT_SPP: u64 = 16_384;
/// Pixel samples of each direct render of the integrator.
pub const DIRECT_SPP: u32 = 16_384;
/// N of the direct renders.
pub const DIRECT_MIS_SAMPLES: [u32; 3] = [1, 2, 10];
const SEED: u32 = 0x000f_1613;
const DIRECT_SEED: u32 = 0x000f_1614;
/// Upscaling of the written PNGs (the inset is small).
const ZOOM: u32 = 6;

/// fig12's camera block, replaced by the inset's.
const FIG12_CAMERA: &str =
    "from = [0.0, 0.05, 2.2]\nto = [0.0, -0.03, 0.0]\nfov = 30.0\nwidth = 160\nheight = 120\n";
/// The inset: a 6° view centred on the warm light (0.12, 0.02, 0.05), which
/// sits inside the cloud; about 6× magnified against fig12. Pixel centres,
/// no jitter, so a pixel's bias is that of one ray.
const INSET_CAMERA: &str = "from = [0.0, 0.05, 2.2]\nto = [0.12, 0.02, 0.05]\nfov = 6.0\n\
    width = 32\nheight = 24\n";

/// The fig12 scene seen through the inset camera, with `extra` overrides.
pub fn scene(extra: &[String]) -> Result<Scene, String> {
    let text = super::fig12::SCENE.replacen(FIG12_CAMERA, INSET_CAMERA, 1);
    if text == super::fig12::SCENE {
        return Err("fig13: fig12's camera block changed; update FIG12_CAMERA".into());
    }
    let text = format!("{text}\n[render]\npixel_jitter = false\n");
    let desc = parse_scene(&text, "fig13 scene", extra).map_err(|e| e.0)?;
    Scene::build(desc, Path::new(".")).map_err(|e| e.0)
}

/// Running sum and sum of squares of one scalar.
#[derive(Clone, Copy, Debug, Default)]
struct Acc {
    s: f64,
    s2: f64,
}

impl Acc {
    fn add(&mut self, x: f64) {
        self.s += x;
        self.s2 += x * x;
    }
    fn mean(&self, n: f64) -> f64 {
        self.s / n
    }
    /// Variance of the mean of `n` samples (sample variance / n).
    fn var_of_mean(&self, n: f64) -> f64 {
        let m = self.s / n;
        ((self.s2 / n - m * m) * n / (n - 1.0)).max(0.0) / n
    }
}

const K: usize = MIS_SAMPLES.len();

#[derive(Clone, Debug, Default)]
struct PixelStats {
    reference_rgb: [f64; 3],
    reference: Acc,
    /// Per N: naive error, jackknife error, naive − jackknife.
    err: [[Acc; 3]; K],
}

fn mean_rgb(v: Vec3) -> f64 {
    (v.x as f64 + v.y as f64 + v.z as f64) / 3.0
}

fn shortcut(s: &Scene, pm: &PointMis, spp: u32) -> Result<Vec<PixelStats>, String> {
    let (w, h) = (s.camera.width, s.camera.height);
    (0..w * h)
        .into_par_iter()
        .map(|pixel| {
            let (x, y) = (pixel % w, pixel / w);
            let mut st = PixelStats::default();
            let mut errors = [[Vec3::ZERO; 2]; K];
            for sample in 0..spp {
                let key = SampleKey {
                    seed: SEED,
                    pixel,
                    sample,
                    dimension: 0,
                };
                let l = pm
                    .eq10_weight_errors(s, x, y, key, &MIS_SAMPLES, &mut errors)
                    .ok_or_else(|| "fig13: the medium must use nearest filtering".to_string())?;
                let e: Vec<[f64; 2]> = errors
                    .iter()
                    .map(|e| [mean_rgb(e[0]), mean_rgb(e[1])])
                    .collect();
                if !l.to_array().iter().all(|c| c.is_finite())
                    || e.iter().flatten().any(|c| !c.is_finite())
                {
                    return Err(format!("fig13: non-finite sample at pixel {pixel}"));
                }
                for c in 0..3 {
                    st.reference_rgb[c] += l.to_array()[c] as f64;
                }
                st.reference.add(mean_rgb(l));
                for (acc, e) in st.err.iter_mut().zip(&e) {
                    acc[0].add(e[0]);
                    acc[1].add(e[1]);
                    acc[2].add(e[0] - e[1]);
                }
            }
            st.reference_rgb.iter_mut().for_each(|c| *c /= spp as f64);
            Ok(st)
        })
        .collect()
}

/// Image-wide summary of one per-pixel quantity.
#[derive(Clone, Copy, Debug)]
pub struct Bias {
    /// Image mean of the per-pixel mean.
    pub mean: f64,
    /// Its standard error (pixels are independent).
    pub se: f64,
    /// √(mean over pixels of (mean² − var of mean)): RMS per-pixel bias with
    /// the noise's contribution to the squares removed (0 if negative).
    pub rms: f64,
    /// Median over pixels of the per-pixel standard error.
    pub median_pixel_se: f64,
}

fn summarise(means: &[f64], vars: &[f64]) -> Bias {
    let n = means.len() as f64;
    let mean = means.iter().sum::<f64>() / n;
    let se = vars.iter().sum::<f64>().sqrt() / n;
    let ms = means.iter().zip(vars).map(|(m, v)| m * m - v).sum::<f64>() / n;
    let mut ses: Vec<f64> = vars.iter().map(|v| v.sqrt()).collect();
    ses.sort_by(|a, b| a.total_cmp(b));
    Bias {
        mean,
        se,
        rms: ms.max(0.0).sqrt(),
        median_pixel_se: ses[ses.len() / 2],
    }
}

/// One row of the result table.
#[derive(Clone, Debug)]
pub struct Row {
    pub mis_samples: u32,
    pub naive: Bias,
    pub jackknife: Bias,
    /// naive − jackknife on common random numbers.
    pub difference: Bias,
    /// Per-pixel bias maps (mean RGB).
    pub naive_map: Vec<f64>,
    pub jackknife_map: Vec<f64>,
}

/// The integrator itself: bias of a render against the shortcut's reference.
#[derive(Clone, Debug)]
pub struct DirectRow {
    pub strategy: &'static str,
    pub mis_samples: u32,
    pub bias: Bias,
    pub seconds: f64,
}

pub struct Results {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seconds: f64,
    pub reference_rgb: Vec<[f64; 3]>,
    pub reference: Bias,
    pub rows: Vec<Row>,
    pub direct: Vec<DirectRow>,
}

fn point_mis(s: &Scene) -> Result<&PointMis, String> {
    match &s.integrator {
        IntegratorKind::PointMis(p) => Ok(p),
        _ => Err("fig13: scene integrator is not point_mis".into()),
    }
}

pub fn compute(spp: u32, direct_spp: u32) -> Result<Results, String> {
    let s = scene(&["integrator.strategy=mis_jackknife_biased".into()])?;
    let pm = point_mis(&s)?;
    let (width, height) = (s.camera.width, s.camera.height);
    let (px, seconds) = clocked(|| shortcut(&s, pm, spp));
    let px = px?;
    let n = spp as f64;
    let ref_means: Vec<f64> = px.iter().map(|p| p.reference.mean(n)).collect();
    let ref_vars: Vec<f64> = px.iter().map(|p| p.reference.var_of_mean(n)).collect();
    let reference = summarise(&ref_means, &ref_vars);
    let rows = MIS_SAMPLES
        .iter()
        .enumerate()
        .map(|(k, &mis_samples)| {
            let get = |j: usize| -> (Vec<f64>, Vec<f64>) {
                (
                    px.iter().map(|p| p.err[k][j].mean(n)).collect(),
                    px.iter().map(|p| p.err[k][j].var_of_mean(n)).collect(),
                )
            };
            let (nm, nv) = get(0);
            let (jm, jv) = get(1);
            let (dm, dv) = get(2);
            Row {
                mis_samples,
                naive: summarise(&nm, &nv),
                jackknife: summarise(&jm, &jv),
                difference: summarise(&dm, &dv),
                naive_map: nm,
                jackknife_map: jm,
            }
        })
        .collect();
    let direct = direct_renders(direct_spp, &ref_means, &ref_vars)?;
    Ok(Results {
        width,
        height,
        spp,
        seconds,
        reference_rgb: px.iter().map(|p| p.reference_rgb).collect(),
        reference,
        rows,
        direct,
    })
}

/// The integrator itself: `mis_naive` and `mis_jackknife_biased` rendered
/// at `direct_spp` for each of [`DIRECT_MIS_SAMPLES`], their bias against
/// the shortcut's reference (none when `direct_spp` ≤ 1).
fn direct_renders(
    direct_spp: u32,
    ref_means: &[f64],
    ref_vars: &[f64],
) -> Result<Vec<DirectRow>, String> {
    let mut direct = Vec::new();
    if direct_spp > 1 {
        for strategy in ["mis_naive", "mis_jackknife_biased"] {
            for n_mis in DIRECT_MIS_SAMPLES {
                let s = scene(&[
                    format!("integrator.strategy={strategy}"),
                    format!("integrator.mis_samples={n_mis}"),
                ])?;
                let (f, secs) = clocked(|| render_at(&s, direct_spp, DIRECT_SEED).film);
                if f.nan_samples + f.inf_samples > 0 {
                    return Err(format!("fig13: {strategy}: non-finite samples"));
                }
                // Conservative across channels, as in fig12.
                let (m, v) = rgb_mean_and_var(&f);
                let d: Vec<f64> = m.iter().zip(ref_means).map(|(a, b)| a - b).collect();
                let var: Vec<f64> = v.iter().zip(ref_vars).map(|(a, b)| a + b).collect();
                direct.push(DirectRow {
                    strategy,
                    mis_samples: n_mis,
                    bias: summarise(&d, &var),
                    seconds: secs,
                });
            }
        }
    }
    Ok(direct)
}

fn save_png(
    w: &mut Writer,
    file: &str,
    width: u32,
    height: u32,
    rgb: impl Fn(usize) -> [f32; 3],
) -> Result<(), String> {
    let mut buf = image::RgbImage::new(width * ZOOM, height * ZOOM);
    for y in 0..height * ZOOM {
        for x in 0..width * ZOOM {
            let i = ((y / ZOOM) * width + x / ZOOM) as usize;
            let px = rgb(i).map(|c| (linear_to_srgb(c.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8);
            buf.put_pixel(x, y, image::Rgb(px));
        }
    }
    let path = w.path(file);
    buf.save(&path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    w.record(path);
    Ok(())
}

/// Signed map: black at 0, red positive (too bright), blue negative, full
/// colour at ±`scale`.
fn bias_colour(v: f64, scale: f64) -> [f32; 3] {
    let u = (v / scale).clamp(-1.0, 1.0) as f32;
    if u >= 0.0 {
        [u, 0.25 * u, 0.0]
    } else {
        [0.0, -0.25 * u, -u]
    }
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let spp = trials.unwrap_or(DEFAULT_SPP).clamp(2, 1 << 22) as u32;
    let r = compute(spp, DIRECT_SPP)?;
    let scale = write_images(w, &r)?;
    write_csv(w, &r)?;
    Ok(summary(&r, scale))
}

/// `reference.png` (99th-percentile mean RGB maps to white) and the bias
/// maps `bias_<variant>_N<N>.png`, on one colour scale for all: 10 % of the
/// image mean, which it returns.
fn write_images(w: &mut Writer, r: &Results) -> Result<f64, String> {
    let (width, height) = (r.width, r.height);
    let image_mean = r.reference.mean;
    // Reference: 99th-percentile mean RGB maps to white.
    let mut lum: Vec<f64> = r
        .reference_rgb
        .iter()
        .map(|p| (p[0] + p[1] + p[2]) / 3.0)
        .collect();
    lum.sort_by(|a, b| a.total_cmp(b));
    let exposure = 1.0 / lum[(lum.len() as f64 * 0.99) as usize].max(1e-9);
    save_png(w, "reference.png", width, height, |i| {
        r.reference_rgb[i].map(|c| (c * exposure) as f32)
    })?;
    // Bias maps: one colour scale for all, 10 % of the image mean.
    let scale = 0.1 * image_mean;
    for row in &r.rows {
        for (name, map) in [
            ("naive", &row.naive_map),
            ("jackknife_biased", &row.jackknife_map),
        ] {
            save_png(
                w,
                &format!("bias_{name}_N{}.png", row.mis_samples),
                width,
                height,
                |i| bias_colour(map[i], scale),
            )?;
        }
    }
    Ok(scale)
}

/// `fig13.csv`: every bias, of the shortcut's weight errors and of the
/// direct renders.
fn write_csv(w: &mut Writer, r: &Results) -> Result<(), String> {
    let image_mean = r.reference.mean;
    let fmt_row = |variant: &str, n: u32, b: &Bias| -> Vec<String> {
        vec![
            variant.to_string(),
            n.to_string(),
            format!("{:.4e}", b.mean),
            format!("{:.4e}", b.se),
            format!("{:.2}", b.mean / b.se.max(1e-300)),
            format!("{:.5}", b.mean / image_mean),
            format!("{:.4e}", b.rms),
            format!("{:.4e}", b.median_pixel_se),
        ]
    };
    let mut csv = Vec::new();
    for row in &r.rows {
        csv.push(fmt_row("mis_naive", row.mis_samples, &row.naive));
        csv.push(fmt_row(
            "mis_jackknife_biased",
            row.mis_samples,
            &row.jackknife,
        ));
        csv.push(fmt_row(
            "naive_minus_jackknife",
            row.mis_samples,
            &row.difference,
        ));
    }
    for d in &r.direct {
        csv.push(fmt_row(
            &format!("direct_{}", d.strategy),
            d.mis_samples,
            &d.bias,
        ));
    }
    w.csv(
        "fig13.csv",
        &[
            "variant",
            "mis_samples",
            "bias_mean_rgb",
            "std_error",
            "z",
            "relative_bias",
            "rms_pixel_bias",
            "median_pixel_std_error",
        ],
        &csv,
    )
}

/// The finding: the table of biases with their z scores, per N and per
/// direct render.
fn summary(r: &Results, scale: f64) -> String {
    let (width, height, spp) = (r.width, r.height, r.spp);
    let image_mean = r.reference.mean;
    let pct = |x: f64| 100.0 * x / image_mean;
    let mut md = format!(
        "Inset of the fig12 scene (6° view centred on the warm point light inside the cloud), \
         {width}×{height} px, pixel centres; light-ray transmittance jackknife N = 10. \
         Shortcut pass: {spp} spp in {:.1} s, every sample evaluating Eq. 10 with exact weights \
         (reference) and the weight errors of the naive and jackknife estimates for \
         N = {:?} on common random numbers. Reference image mean {image_mean:.5} ± {:.1e}.\n\n\
         | N | `mis_naive` bias | z | `mis_jackknife_biased` bias | z | naive − jackknife | z | RMS pixel bias naive / jackknife |\n\
         |---|---|---|---|---|---|---|---|\n",
        r.seconds, MIS_SAMPLES, r.reference.se
    );
    for row in &r.rows {
        md.push_str(&format!(
            "| {} | {:+.3e} ± {:.1e} ({:+.3} %) | {:+.1} | {:+.3e} ± {:.1e} ({:+.3} %) | {:+.1} | {:+.3e} ± {:.1e} | {:+.1} | {:.2e} / {:.2e} |\n",
            row.mis_samples,
            row.naive.mean,
            row.naive.se,
            pct(row.naive.mean),
            row.naive.mean / row.naive.se,
            row.jackknife.mean,
            row.jackknife.se,
            pct(row.jackknife.mean),
            row.jackknife.mean / row.jackknife.se,
            row.difference.mean,
            row.difference.se,
            row.difference.mean / row.difference.se,
            row.naive.rms,
            row.jackknife.rms,
        ));
    }
    if !r.direct.is_empty() {
        md.push_str(&format!(
            "\nDirect renders by `point_mis` ({DIRECT_SPP} spp, seed independent of the \
             reference), bias against the shortcut's reference:\n\n\
             | strategy | N | bias | z | relative | time |\n|---|---|---|---|---|---|\n"
        ));
        for d in &r.direct {
            md.push_str(&format!(
                "| `{}` | {} | {:+.3e} ± {:.1e} | {:+.1} | {:+.3} % | {:.1} s |\n",
                d.strategy,
                d.mis_samples,
                d.bias.mean,
                d.bias.se,
                d.bias.mean / d.bias.se,
                pct(d.bias.mean),
                d.seconds
            ));
        }
    }
    md.push_str(&format!(
        "\nBias maps `bias_<variant>_N<N>.png`: red = too bright, blue = too dark, full colour \
         at ±10 % of the image mean ({scale:.2e}).\n"
    ));
    md
}

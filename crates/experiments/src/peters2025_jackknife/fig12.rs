//! Peters 2025 Fig. 12 and Fig. 13: a cloud lit by two point lights inside it,
//! rendered with the `point_mis` integrator's six distance-sampling
//! strategies at equal pixel samples (16 spp; the MIS variants take two
//! distance samples each). Like the paper, the grid uses nearest-neighbour
//! filtering (so Miller et al.'s weights are well defined) and the light
//! ray's transmittance is the jackknife estimator with N = 10.
//!
//! Measured: SMAPE (ε = 0.01, the paper's metric) of each 16-spp image
//! against a high-spp `mis_jackknife` reference rendered with another seed,
//! and — for Fig. 13's question — the image-wide mean signed bias of every
//! strategy after `BIAS_SPP` samples, with its standard error. The light
//! ray's estimator is common to all strategies and the reference, so a
//! bias here can only come from the MIS weights (Eq. 10 variants).
//!
//! The Disney cloud is not redistributable here; fogbank's procedural cloud
//! (`procedural::cloud_grid`) stands in for it.

use crate::harness::protocol::spp;
use crate::harness::Writer;
use fogbank_eval::image_io::Image;
use fogbank_eval::metrics::smape::smape;
use fogbank_render::integrators::point_mis::Strategy;
use fogbank_render::{parse_scene, render_observed, Film, Progress, RenderOptions, Scene};
use std::path::Path;

/// Pixel samples of the compared images (the paper's 16 spp).
pub const SPP: u32 = 16;
/// Pixel samples per strategy for the bias column.
pub const BIAS_SPP: u32 = 512;
/// Reference pixel samples (`--trials` overrides).
pub const DEFAULT_REFERENCE_SPP: u64 = 8192;
const SEED: u32 = 0x000f_1612;
const REFERENCE_SEED: u32 = 0x000f_1613;

/// The scene: a dense procedural cumulus (extinction up to ≈ 24 per unit
/// length, so the interior is optically thick), two point lights inside it,
/// nearest filtering, jackknife (N = 10) on the light ray.
pub const SCENE: &str = include_str!("fig12.toml");

pub fn scene(strategy: Strategy) -> Result<Scene, String> {
    let desc = parse_scene(
        SCENE,
        "fig12 scene",
        &[format!("integrator.strategy={}", strategy.name())],
    )
    .map_err(|e| e.0)?;
    Scene::build(desc, Path::new(".")).map_err(|e| e.0)
}

/// One strategy's measurements.
#[derive(Clone, Debug)]
pub struct Row {
    pub strategy: Strategy,
    /// Mean image after `SPP` passes.
    pub image: Vec<[f32; 3]>,
    /// Render time of those passes.
    pub seconds: f64,
    pub smape: f64,
    /// Image-wide mean of (mean RGB − reference mean RGB) after `BIAS_SPP`.
    pub bias: f64,
    /// Its standard error (conservative across channels).
    pub bias_se: f64,
    pub lookups_per_sample: f64,
}

fn to_image(film_w: u32, film_h: u32, rgb: Vec<[f32; 3]>) -> Image {
    Image::new(film_w as usize, film_h as usize, rgb)
}

/// Renders `spp` passes, returning the mean after `SPP` passes, its time,
/// and the final film.
fn render_strategy(s: &Scene, spp: u32, seed: u32) -> (Vec<[f32; 3]>, f64, Film) {
    let mut early = (Vec::new(), 0.0);
    let mut passes = 0;
    let r = render_observed(
        s,
        &RenderOptions::new(spp, seed),
        &Progress::default(),
        &mut |film, secs| {
            passes += 1;
            if passes == SPP {
                early = (film.mean(), secs);
            }
        },
    );
    (early.0, early.1, r.film)
}

/// Per-pixel mean RGB value and a conservative variance of it (the
/// standard deviation of a channel mean is at most the mean of the three);
/// fig13 uses it too.
pub(super) fn rgb_mean_and_var(f: &Film) -> (Vec<f64>, Vec<f64>) {
    let (m, v) = (f.mean(), f.variance_of_mean());
    let mean = m
        .iter()
        .map(|p| p.iter().map(|&c| c as f64).sum::<f64>() / 3.0)
        .collect();
    let var = v
        .iter()
        .map(|p| {
            let sd = p.iter().map(|&c| (c as f64).sqrt()).sum::<f64>() / 3.0;
            sd * sd
        })
        .collect();
    (mean, var)
}

/// Everything the figure needs: the reference film and one row per strategy.
pub fn compute(reference_spp: u32, bias_spp: u32) -> Result<(Film, Vec<Row>), String> {
    let reference = render_strategy(
        &scene(Strategy::MisJackknife)?,
        reference_spp.max(SPP),
        REFERENCE_SEED,
    )
    .2;
    let (w, h) = (reference.width, reference.height);
    let ref_image = to_image(w, h, reference.mean());
    let (ref_m, ref_v) = rgb_mean_and_var(&reference);
    let mut rows = Vec::new();
    for strategy in Strategy::ALL {
        let s = scene(strategy)?;
        let (image, seconds, film) = render_strategy(&s, bias_spp.max(SPP), SEED);
        if film.nan_samples + film.inf_samples > 0 {
            return Err(format!(
                "{}: {} NaN and {} Inf samples",
                strategy.name(),
                film.nan_samples,
                film.inf_samples
            ));
        }
        let smape = smape(&ref_image, &to_image(w, h, image.clone()))?;
        let (m, v) = rgb_mean_and_var(&film);
        let n = m.len() as f64;
        let bias = (0..m.len()).map(|i| m[i] - ref_m[i]).sum::<f64>() / n;
        let bias_se = (0..m.len()).map(|i| v[i] + ref_v[i]).sum::<f64>().sqrt() / n;
        rows.push(Row {
            strategy,
            image,
            seconds,
            smape,
            bias,
            bias_se,
            lookups_per_sample: film.lookups as f64 / film.total_samples().max(1) as f64,
        });
    }
    Ok((reference, rows))
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let reference_spp = spp(trials, DEFAULT_REFERENCE_SPP);
    let (reference, rows) = compute(reference_spp, BIAS_SPP)?;
    write_images(w, &reference, &rows)?;
    let image_mean = reference.image_mean().iter().sum::<f64>() / 3.0;
    write_csv(w, &rows, image_mean)?;
    let (width, height) = (reference.width, reference.height);
    Ok(summary(&rows, width, height, reference_spp, image_mean))
}

/// `reference.png` and `<strategy>_16spp.png`, all at the exposure that
/// maps the reference's 99th-percentile mean RGB value to 1.
fn write_images(w: &mut Writer, reference: &Film, rows: &[Row]) -> Result<(), String> {
    let (width, height) = (reference.width, reference.height);
    let ref_mean = reference.mean();
    // Exposure: the reference's 99th-percentile mean RGB value maps to 1.
    let mut lum: Vec<f32> = ref_mean
        .iter()
        .map(|p| (p[0] + p[1] + p[2]) / 3.0)
        .collect();
    lum.sort_by(|a, b| a.total_cmp(b));
    let p99 = lum[(lum.len() as f64 * 0.99) as usize].max(1e-6);
    let exposure = (1.0 / p99).log2();
    w.png("reference.png", width, height, &ref_mean, exposure)?;
    for r in rows {
        let name = format!("{}_{SPP}spp.png", r.strategy.name());
        w.png(&name, width, height, &r.image, exposure)?;
    }
    Ok(())
}

/// `fig12.csv`: SMAPE, time, lookups and bias per strategy.
fn write_csv(w: &mut Writer, rows: &[Row], image_mean: f64) -> Result<(), String> {
    let csv: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.strategy.name().to_string(),
                r.strategy.distance_samples().to_string(),
                format!("{:.4}", r.smape),
                format!("{:.3}", r.seconds),
                format!("{:.1}", r.lookups_per_sample),
                format!("{:.6}", r.bias),
                format!("{:.6}", r.bias_se),
                format!("{:.5}", r.bias / image_mean),
            ]
        })
        .collect();
    w.csv(
        "fig12.csv",
        &[
            "strategy",
            "distance_samples_per_spp",
            "smape_16spp",
            "seconds_16spp",
            "lookups_per_pixel_sample",
            "bias_mean_rgb",
            "bias_std_error",
            "relative_bias",
        ],
        &csv,
    )
}

/// The finding: which MIS variants beat the better single strategy, and
/// Eq. 10's bias with naive and jackknife weights.
fn summary(rows: &[Row], width: u32, height: u32, reference_spp: u32, image_mean: f64) -> String {
    let best_single = rows
        .iter()
        .filter(|r| r.strategy.distance_samples() == 1)
        .map(|r| r.smape)
        .fold(f64::INFINITY, f64::min);
    let mut md = format!(
        "Procedural cloud (96³, nearest filter, σ_t ≤ 24) with two point lights inside, \
         {width}×{height} px; light-ray transmittance: jackknife, N = 10; MIS weights from \
         optical-depth estimates with N = 10. SMAPE (ε = 0.01) of {SPP}-spp images against a \
         {reference_spp}-spp `mis_jackknife` reference (independent seed). Bias: image-wide mean \
         of mean-RGB difference after {BIAS_SPP} spp against the reference (± one standard \
         error); the image mean is {image_mean:.5}.\n\n\
         | strategy | distance samples / spp | SMAPE @ {SPP} spp | time @ {SPP} spp | lookups / sample | bias @ {BIAS_SPP} spp | bias / SE | relative bias |\n\
         |---|---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        md.push_str(&format!(
            "| `{}` | {} | {:.4} | {:.2} s | {:.0} | {:+.6} ± {:.6} | {:+.1} | {:+.2} % |\n",
            r.strategy.name(),
            r.strategy.distance_samples(),
            r.smape,
            r.seconds,
            r.lookups_per_sample,
            r.bias,
            r.bias_se,
            r.bias / r.bias_se.max(1e-300),
            100.0 * r.bias / image_mean,
        ));
    }
    let get = |s: Strategy| {
        rows.iter()
            .find(|r| r.strategy == s)
            .expect("all strategies rendered")
    };
    let mis_beat = [
        Strategy::MisMiller,
        Strategy::MisNaive,
        Strategy::MisJackknife,
        Strategy::MisJackknifeBiased,
    ]
    .iter()
    .filter(|&&s| get(s).smape < best_single)
    .map(|s| format!("`{}`", s.name()))
    .collect::<Vec<_>>();
    let (naive, jk) = (get(Strategy::MisNaive), get(Strategy::MisJackknifeBiased));
    md.push_str(&format!(
        "\nMIS variants with lower SMAPE than the better single strategy ({best_single:.4}): {}.\n\
         Eq. 10 bias: `mis_naive` {:+.2} % ({:+.1} SE), `mis_jackknife_biased` {:+.2} % ({:+.1} SE).\n",
        if mis_beat.is_empty() { "none".to_string() } else { mis_beat.join(", ") },
        100.0 * naive.bias / image_mean,
        naive.bias / naive.bias_se,
        100.0 * jk.bias / image_mean,
        jk.bias / jk.bias_se,
    ));
    md
}

//! Peters 2025 Fig. 1: a cloud under direct illumination from a light probe at
//! 32 spp, with the NEE transmittance estimator as the only difference.
//! The paper's finding: biased ray marching overestimates transmittance
//! visibly, the jackknife's bias is negligible, it has fewer fireflies than
//! unbiased ray marching and lower variance than the track-length estimate
//! and ratio tracking.
//!
//! Scene: `scenes/fig1.toml` (fogbank's procedural cloud, a synthetic sky
//! probe; the paper uses the Intel cloud) rendered with `direct` at a
//! reduced resolution. Per estimator, `trials` spp give each pixel's mean
//! and the variance of a 32-spp pixel; the reference is ratio tracking at
//! 4 × `trials` spp. Bias is the mean signed difference over the pixels the
//! cloud covers, with its standard error from both renders' variances.

use crate::harness::protocol::{render_at, spp};
use crate::harness::Writer;
use fogbank_estimators::Estimator;
use fogbank_render::{Film, Scene};
use fogbank_scene::load_scene;
use std::path::Path;

pub const SCENE_FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/fig1.toml");
pub const DEFAULT_TRIALS: u64 = 512;
pub const ESTIMATORS: [&str; 5] = [
    "biased_ray_marching",
    "jackknife",
    "unbiased_ray_marching",
    "track_length",
    "ratio_tracking",
];
const SPP: f64 = 32.0;

fn scene(width: u32, height: u32) -> Result<Scene, String> {
    load_scene(
        Some(Path::new(SCENE_FILE)),
        &[
            format!("camera.width={width}"),
            format!("camera.height={height}"),
        ],
    )
    .map_err(|e| e.0)
}

/// Peters 2025 compares the plain estimators: ratio tracking without the
/// roulette fogbank plays by default (`roulette = 0`).
fn with_estimator(scene: &Scene, name: &str) -> Result<Scene, String> {
    let e = Estimator::parse(name)
        .ok_or_else(|| format!("unknown estimator {name}"))?
        .without_roulette();
    let mut s = scene.clone();
    s.integrator = s.integrator.with_estimator(e);
    Ok(s)
}

fn run_film(scene: &Scene, spp: u32, seed: u32) -> (Film, f64) {
    let r = render_at(scene, spp, seed);
    (r.film, r.seconds)
}

pub struct Row {
    pub estimator: &'static str,
    /// Milliseconds per 32-spp frame at the scene file's full resolution.
    pub ms_per_frame: f64,
    pub lookups_per_sample: f64,
    pub mean_bias: f64,
    pub mean_bias_se: f64,
    /// Mean over covered pixels of the standard deviation of a 32-spp pixel.
    pub std_32: f64,
    /// Largest per-pixel standard deviation of a 32-spp pixel (fireflies).
    pub max_std_32: f64,
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let trials = spp(trials, DEFAULT_TRIALS);
    let (rows, radiance) = measure(w, trials)?;
    let table = write_table(w, &rows, radiance)?;
    Ok(summary(&rows, radiance, trials, &table))
}

/// The reference (ratio tracking at 4 × `trials` spp), then per estimator
/// its statistics at 160×100 and its 32-spp image at 640×400
/// (`<estimator>_32spp.png`); returns the rows and the mean radiance of
/// the covered pixels.
fn measure(w: &mut Writer, trials: u32) -> Result<(Vec<Row>, f64), String> {
    let full = scene(640, 400)?;
    let full_pixels = 640.0 * 400.0;
    let base = scene(160, 100)?;
    let pixels = 160.0 * 100.0;
    let (reference, _) = run_film(&with_estimator(&base, "ratio_tracking")?, 4 * trials, 1);
    let (ref_mean, ref_var) = (reference.mean(), reference.variance_of_mean());
    // Pixels the cloud covers: the reference has noise there.
    let covered: Vec<usize> = (0..ref_var.len())
        .filter(|&i| ref_var[i].iter().any(|&v| v > 0.0))
        .collect();
    let radiance: f64 = covered
        .iter()
        .map(|&i| ref_mean[i].iter().map(|&c| c as f64).sum::<f64>() / 3.0)
        .sum::<f64>()
        / covered.len().max(1) as f64;
    let mut rows = Vec::new();
    for (k, name) in ESTIMATORS.iter().enumerate() {
        let s = with_estimator(&base, name)?;
        let (film, seconds) = run_film(&s, trials, 10 + k as u32);
        let (mean, var) = (film.mean(), film.variance_of_mean());
        let (mut bias, mut bias_var, mut std, mut max_std) = (0.0, 0.0, 0.0, 0.0f64);
        for &i in &covered {
            for c in 0..3 {
                bias += mean[i][c] as f64 - ref_mean[i][c] as f64;
                bias_var += var[i][c] as f64 + ref_var[i][c] as f64;
                let sd = (var[i][c] as f64 * trials as f64 / SPP).sqrt();
                std += sd;
                max_std = max_std.max(sd);
            }
        }
        let n = 3.0 * covered.len().max(1) as f64;
        rows.push(Row {
            estimator: name,
            ms_per_frame: seconds / (trials as f64 * pixels) * SPP * full_pixels * 1e3,
            lookups_per_sample: film.lookups as f64 / film.total_samples().max(1) as f64,
            mean_bias: bias / n,
            mean_bias_se: bias_var.sqrt() / n,
            std_32: std / n,
            max_std_32: max_std,
        });
        // The figure: each estimator at 32 spp, full resolution.
        let (img, _) = run_film(&with_estimator(&full, name)?, SPP as u32, 99);
        save_png(w, &format!("{name}_32spp.png"), &img)?;
    }
    Ok((rows, radiance))
}

/// Writes `fig1.csv` and returns the same rows as a Markdown table.
fn write_table(w: &mut Writer, rows: &[Row], radiance: f64) -> Result<String, String> {
    let mut table = String::from(
        "| estimator | ms / 32-spp frame (640×400) | lookups / sample | mean bias (± SE) | relative bias | mean std @32 spp | max std @32 spp |\n|---|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut csv = Vec::new();
    for r in rows {
        table += &format!(
            "| {} | {:.0} | {:.1} | {:+.5} (± {:.5}) | {:+.2} % | {:.4} | {:.3} |\n",
            r.estimator,
            r.ms_per_frame,
            r.lookups_per_sample,
            r.mean_bias,
            r.mean_bias_se,
            100.0 * r.mean_bias / radiance,
            r.std_32,
            r.max_std_32
        );
        csv.push(vec![
            r.estimator.to_string(),
            format!("{:.3}", r.ms_per_frame),
            format!("{:.3}", r.lookups_per_sample),
            format!("{:.6e}", r.mean_bias),
            format!("{:.6e}", r.mean_bias_se),
            format!("{:.6e}", r.std_32),
            format!("{:.6e}", r.max_std_32),
        ]);
    }
    w.csv(
        "fig1.csv",
        &[
            "estimator",
            "ms_per_frame",
            "lookups_per_sample",
            "mean_bias",
            "mean_bias_se",
            "std_32spp",
            "max_std_32spp",
        ],
        &csv,
    )?;
    Ok(table)
}

/// The finding: the jackknife's bias, noise, fireflies and time against
/// the other estimators.
fn summary(rows: &[Row], radiance: f64, trials: u32, table: &str) -> String {
    let find = |n: &str| rows.iter().find(|r| r.estimator == n).expect("row");
    let (jk, brm, urm, tl, rt) = (
        find("jackknife"),
        find("biased_ray_marching"),
        find("unbiased_ray_marching"),
        find("track_length"),
        find("ratio_tracking"),
    );
    format!(
        "Direct illumination of `scenes/fig1.toml` under its light probe, `direct` integrator, \
         statistics at 160×100 from {trials} spp per estimator against ratio tracking at {} spp \
         (mean radiance of covered pixels {radiance:.4}); images `*_32spp.png` at 640×400, 32 spp.\n\n\
         {table}\n\
         Findings: |bias| jackknife / biased ray marching = {:.3}; std at 32 spp jackknife / \
         track-length = {:.2}, / ratio tracking = {:.2}; max std (fireflies) jackknife / unbiased \
         ray marching = {:.2}; time jackknife / track-length = {:.2}, / ratio tracking = {:.2} \
         (CPU; the seed's timings are GPU).",
        4 * trials,
        jk.mean_bias.abs() / brm.mean_bias.abs().max(1e-12),
        jk.std_32 / tl.std_32,
        jk.std_32 / rt.std_32,
        jk.max_std_32 / urm.max_std_32.max(1e-12),
        jk.ms_per_frame / tl.ms_per_frame,
        jk.ms_per_frame / rt.ms_per_frame,
    )
}

fn save_png(w: &mut Writer, file: &str, film: &Film) -> Result<(), String> {
    let bytes: Vec<u8> = film
        .mean()
        .iter()
        .flat_map(|p| {
            p.map(|c| {
                (fogbank_eval::image_io::linear_to_srgb(c).clamp(0.0, 1.0) * 255.0 + 0.5) as u8
            })
        })
        .collect();
    let path = w.path(file);
    image::save_buffer(
        &path,
        &bytes,
        film.width,
        film.height,
        image::ColorType::Rgb8,
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    w.record(path);
    Ok(())
}

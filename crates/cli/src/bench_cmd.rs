//! `fogbank bench`: per-estimator cost and accuracy of the transmittance view
//! of a procedural cloud, measured side by side in one run.
//!
//! Timing: `--frames` 1-spp frames at `--size`² for each thread count.
//! Accuracy: mean |bias| and mean single-frame std against
//! `analytic_trilinear` over `--stats-frames` frames at `--stats-size`²
//! through pixel centres (bias needs many frames, so this runs smaller).

use crate::common::{thread_pool, CliResult};
use clap::Args;
use fogbank_estimators::Estimator;
use fogbank_eval::experiments::harness::timing::median;
use fogbank_eval::{transmittance_stats, Backend};
use fogbank_render::{parse_scene, Progress, RenderOptions, Scene};
use std::path::Path;

#[derive(Args)]
pub struct BenchArgs {
    /// Cloud resolution (voxels per side).
    #[arg(long, default_value_t = 256)]
    pub resolution: u32,
    /// Image width and height for timing.
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    /// Frames (1 spp each) per timing.
    #[arg(long, default_value_t = 4)]
    pub frames: u32,
    /// Thread counts to time, comma separated.
    #[arg(long, default_value = "1,2", value_delimiter = ',')]
    pub threads: Vec<usize>,
    /// Estimators (comma separated), each `NAME` or `NAME:KEY=VALUE:…`
    /// (`ratio_tracking:roulette=0.1`); default all.
    #[arg(long, value_delimiter = ',')]
    pub estimators: Vec<String>,
    /// Extinction scale of the cloud.
    #[arg(long, default_value_t = 60.0)]
    pub sigma_t_scale: f32,
    /// Image size for the bias/std measurement (0 skips it).
    #[arg(long, default_value_t = 64)]
    pub stats_size: u32,
    /// Frames for the bias/std measurement.
    #[arg(long, default_value_t = 2048)]
    pub stats_frames: u32,
    /// Devices to time, comma separated: `cpu` (at each of --threads) and/or
    /// `gpu` (wgpu; kernel time from timestamp queries when available).
    #[arg(long, default_value = "cpu", value_delimiter = ',')]
    pub device: Vec<String>,
    /// Also write the table as JSON.
    #[arg(long)]
    pub json: Option<std::path::PathBuf>,
    /// Also time these integrators (comma separated: transmittance, direct,
    /// volpath, point_mis, restir, ament, visopt) on the cloud lit by a sky
    /// and a sun, at each of --threads on the CPU, with each thread count's
    /// speed-up over the first: the thread-scaling table.
    #[arg(long, value_delimiter = ',')]
    pub integrators: Vec<String>,
    /// Rounds of the thread-scaling table: with N > 1, one untimed warm-up
    /// render per thread count, then N rounds, each timing every thread
    /// count in turn; the table gives the median ms per frame, its range,
    /// and the median of the rounds' speed-ups (pairing each round's
    /// timings keeps the ratio meaningful on a machine whose speed drifts).
    #[arg(long, default_value_t = 1)]
    pub repeat: u32,
}

fn cloud_scene(
    size: u32,
    resolution: u32,
    scale: f32,
    frames: u32,
) -> Result<Scene, Box<dyn std::error::Error>> {
    Ok(Scene::build(
        parse_scene(
            &cloud_text(size, resolution, scale, frames),
            "bench scene",
            &[],
        )?,
        Path::new("."),
    )?)
}

fn cloud_text(size: u32, resolution: u32, scale: f32, frames: u32) -> String {
    format!(
        r#"
[camera]
from = [0.0, 0.05, 2.2]
to = [0.0, -0.05, 0.0]
fov = 32.0
width = {size}
height = {size}
[[media]]
density = {{ procedural = "cloud", resolution = {resolution}, seed = 7 }}
sigma_t_scale = {scale}
filter = "stochastic_trilinear"
[render]
spp = {frames}
"#
    )
}

/// The thread-scaling table: each integrator on the lit cloud at each
/// thread count, ms per frame and the speed-up over the first count.
fn integrator_scaling(a: &BenchArgs) -> CliResult {
    let cloud = cloud_text(a.size, a.resolution, a.sigma_t_scale, a.frames);
    let sky_and_sun = "[[lights]]\ntype = \"constant\"\nradiance = [0.55, 0.7, 1.0]\n\
                       [[lights]]\ntype = \"directional\"\ndirection = [-0.4, -0.8, -0.3]\nirradiance = [3.0, 2.9, 2.7]\n";
    // point_mis is the jackknife paper's point-light integrator; ament takes point lights.
    let points =
        "[[lights]]\ntype = \"point\"\nposition = [0.3, 0.2, 0.1]\nintensity = [1.0, 0.85, 0.7]\n";
    let rounds = a.repeat.max(1) as usize;
    println!();
    println!(
        "| integrator | threads | ms/frame (median of {rounds}) | range | speed-up over {} thread(s) (median) |",
        a.threads[0]
    );
    println!("|---|---:|---:|---:|---:|");
    for name in &a.integrators {
        let lights = if name == "point_mis" || name == "ament" {
            points
        } else {
            sky_and_sun
        };
        let desc = parse_scene(
            &(cloud.clone() + lights),
            "bench scene",
            &[format!("integrator.type={name}")],
        )?;
        let scene = Scene::build(desc, Path::new("."))?;
        let pools = a
            .threads
            .iter()
            .map(|&t| thread_pool(Some(t)))
            .collect::<Result<Vec<_>, _>>()?;
        let opts = RenderOptions::new(a.frames, 1);
        let time = |pool: &rayon::ThreadPool| {
            let r = pool.install(|| fogbank_render::render(&scene, &opts, &Progress::default()));
            r.seconds * 1000.0 / a.frames as f64
        };
        if rounds > 1 {
            pools.iter().for_each(|p| {
                time(p);
            });
        }
        // ms[round][thread count]
        let ms: Vec<Vec<f64>> = (0..rounds)
            .map(|_| pools.iter().map(&time).collect())
            .collect();
        for (k, threads) in a.threads.iter().enumerate() {
            let mine: Vec<f64> = ms.iter().map(|r| r[k]).collect();
            let speedup: Vec<f64> = ms.iter().map(|r| r[0] / r[k]).collect();
            let range = format!(
                "{:.1}–{:.1}",
                mine.iter().cloned().fold(f64::INFINITY, f64::min),
                mine.iter().cloned().fold(0.0, f64::max)
            );
            println!(
                "| {name} | {threads} | {:.1} | {range} | {:.2}× |",
                median(mine),
                median(speedup)
            );
        }
    }
    Ok(())
}

pub fn run(a: BenchArgs) -> CliResult {
    let estimators: Vec<Estimator> = if a.estimators.is_empty() {
        Estimator::all()
    } else {
        a.estimators
            .iter()
            .map(|n| Estimator::parse_spec(n))
            .collect::<Result<_, _>>()?
    };
    // Rows name the estimator as given (options included).
    let labels: Vec<String> = if a.estimators.is_empty() {
        estimators.iter().map(|e| e.name().to_string()).collect()
    } else {
        a.estimators.clone()
    };
    eprintln!("building a {}³ cloud ...", a.resolution);
    let mut scene = cloud_scene(a.size, a.resolution, a.sigma_t_scale, a.frames)?;
    let accuracy = accuracy(&a, &scene, &estimators)?;
    let gpu = open_gpu(&a)?;
    println!(
        "| estimator | threads (or gpu) | ms/frame | Mrays/s | lookups/ray | mean abs bias | mean std |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|");
    let mut rows = Vec::new();
    // (backend, threads): the CPU at each thread count, then the GPU.
    let mut runs: Vec<(Backend, usize)> = Vec::new();
    if a.device.iter().any(|d| d == "cpu") {
        runs.extend(a.threads.iter().map(|&t| (Backend::Cpu, t)));
    }
    if let Some(g) = &gpu {
        runs.push((Backend::Gpu(g), 1));
    }
    for (backend, threads) in runs {
        let pool = thread_pool(Some(threads))?;
        for (i, e) in estimators.iter().copied().enumerate() {
            scene.integrator = fogbank_render::integrators::IntegratorKind::Transmittance(
                fogbank_render::integrators::transmittance::Transmittance {
                    estimator: e,
                    background: glam::Vec3::ONE,
                },
            );
            let row = Row {
                label: &labels[i],
                accuracy: accuracy[i],
                threads,
            };
            rows.push(time_row(&a, &scene, backend, &pool, row)?);
        }
    }
    if let Some(p) = &a.json {
        std::fs::write(p, serde_json::to_string_pretty(&rows)?)
            .map_err(|e| format!("{}: {e}", p.display()))?;
    }
    if !a.integrators.is_empty() {
        integrator_scaling(&a)?;
    }
    Ok(())
}

/// (mean |bias|, mean std) of an estimator, when measured.
type Accuracy = Option<(f64, f64)>;

/// Mean |bias| and std of each estimator over `--stats-frames` frames at
/// `--stats-size`² against the exact transmittance (none with size 0).
fn accuracy(
    a: &BenchArgs,
    scene: &Scene,
    estimators: &[Estimator],
) -> Result<Vec<Accuracy>, Box<dyn std::error::Error>> {
    if a.stats_size == 0 {
        return Ok(vec![None; estimators.len()]);
    }
    let mut small = cloud_scene(a.stats_size, a.resolution, a.sigma_t_scale, 1)?;
    small.media = scene.media.clone();
    let pool = thread_pool(a.threads.iter().copied().max())?;
    Ok(estimators
        .iter()
        .map(|&e| {
            eprintln!(
                "accuracy of {} over {} frames at {}² ...",
                e.name(),
                a.stats_frames,
                a.stats_size
            );
            let s = pool
                .install(|| {
                    transmittance_stats(
                        &small,
                        e,
                        Some(Estimator::AnalyticTrilinear),
                        a.stats_frames,
                        3,
                    )
                })
                .summary();
            Some((s.mean_abs_bias, s.mean_std))
        })
        .collect())
}

/// The GPU when `--device` names it.
fn open_gpu(a: &BenchArgs) -> Result<Option<fogbank_gpu::Gpu>, String> {
    for d in &a.device {
        if d != "cpu" && d != "gpu" {
            return Err(format!("--device: `{d}` is not cpu or gpu"));
        }
    }
    if !a.device.iter().any(|d| d == "gpu") {
        return Ok(None);
    }
    let g = fogbank_gpu::Gpu::new().map_err(|e| format!("--device gpu: {e}"))?;
    eprintln!("GPU: {}", g.describe());
    Ok(Some(g))
}

/// One table row's estimator label, accuracy and CPU thread count.
struct Row<'a> {
    label: &'a str,
    accuracy: Option<(f64, f64)>,
    threads: usize,
}

/// Times `--frames` frames of `scene` on `backend` (a GPU after one untimed
/// frame of compilation and upload), prints the row and returns it as JSON.
fn time_row(
    a: &BenchArgs,
    scene: &Scene,
    backend: Backend,
    pool: &rayon::ThreadPool,
    row: Row,
) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    let opts = RenderOptions::new(a.frames, 1);
    if let Backend::Gpu(_) = backend {
        let warm = RenderOptions {
            spp: 1,
            ..opts.clone()
        };
        backend.render(scene, &warm, &Progress::default())?;
    }
    let r = pool.install(|| backend.render(scene, &opts, &Progress::default()))?;
    let rays = (a.size as u64 * a.size as u64 * a.frames as u64) as f64;
    let ms = r.seconds * 1000.0 / a.frames as f64;
    let mrays = rays / r.seconds / 1e6;
    let lpr = r.film.lookups as f64 / rays;
    let (bias, std) = row
        .accuracy
        .map_or(("–".to_string(), "–".to_string()), |(b, s)| {
            (format!("{b:.5}"), format!("{s:.4}"))
        });
    let device = match backend {
        Backend::Cpu => row.threads.to_string(),
        Backend::Gpu(_) => backend.name().to_string(),
    };
    println!(
        "| {} | {} | {:.1} | {:.2} | {:.1} | {} | {} |",
        row.label, device, ms, mrays, lpr, bias, std
    );
    Ok(serde_json::json!({
        "estimator": row.label, "threads": device, "ms_per_frame": ms, "mrays_per_s": mrays,
        "lookups_per_ray": lpr,
        "mean_abs_bias": row.accuracy.map(|v| v.0), "mean_std": row.accuracy.map(|v| v.1),
    }))
}

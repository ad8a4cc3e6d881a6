//! `fogbank bench` as a library call: per-estimator cost and accuracy of
//! the transmittance view of a procedural cloud, measured side by side in
//! one run, and the integrators' thread-scaling table.
//!
//! Timing: `frames` 1-spp frames at `size`² for each thread count (and on
//! the GPU). Accuracy: mean |bias| and mean single-frame std against
//! `analytic_trilinear` over `stats_frames` frames at `stats_size`² through
//! pixel centres (bias needs many frames, so this runs smaller). Rows reach
//! the caller as they are measured, since a whole bench takes minutes.

use crate::error::Error;
use crate::renderer::{threads_or_all, Renderer};
use fogbank_estimators::estimator::AnalyticTrilinear;
use fogbank_estimators::Estimator;
use fogbank_eval::median::median;
use fogbank_eval::{transmittance_stats, Backend};
use fogbank_gpu::Gpu;
use fogbank_render::integrators::transmittance::Transmittance;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, Progress, RenderOptions, Scene};
use serde_json::{json, Value};
use std::path::Path;

/// What to measure; the defaults are `fogbank bench`'s.
#[derive(Clone, Debug)]
pub struct BenchSpec {
    /// Cloud resolution (voxels per side).
    pub resolution: u32,
    /// Image width and height for timing.
    pub size: u32,
    /// Frames (1 spp each) per timing.
    pub frames: u32,
    /// Thread counts to time.
    pub threads: Vec<usize>,
    /// Estimators, each `NAME` or `NAME:KEY=VALUE:…`; empty: all.
    pub estimators: Vec<String>,
    /// Extinction scale of the cloud.
    pub sigma_t_scale: f32,
    /// Image size for the bias/std measurement (0 skips it).
    pub stats_size: u32,
    /// Frames for the bias/std measurement.
    pub stats_frames: u32,
    /// Devices to time: `cpu` (at each thread count) and/or `gpu`.
    pub devices: Vec<String>,
    /// Integrators of the thread-scaling table (none: no table).
    pub integrators: Vec<String>,
    /// Rounds of the thread-scaling table (see [`integrator_scaling`]).
    pub repeat: u32,
}

impl Default for BenchSpec {
    fn default() -> Self {
        BenchSpec {
            resolution: 256,
            size: 512,
            frames: 4,
            threads: vec![1, 2],
            estimators: Vec::new(),
            sigma_t_scale: 60.0,
            stats_size: 64,
            stats_frames: 2048,
            devices: vec!["cpu".into()],
            integrators: Vec::new(),
            repeat: 1,
        }
    }
}

/// One estimator on one device: time and, when measured, accuracy.
#[derive(Clone, Debug)]
pub struct EstimatorRow {
    /// The estimator as given (options included).
    pub label: String,
    /// The CPU's thread count, or the GPU's name.
    pub device: String,
    pub ms_per_frame: f64,
    pub mrays_per_s: f64,
    pub lookups_per_ray: f64,
    /// (mean |bias|, mean std), when measured.
    pub accuracy: Option<(f64, f64)>,
}

impl EstimatorRow {
    /// The row as `fogbank bench --json` writes it.
    pub fn to_json(&self) -> Value {
        json!({
            "estimator": self.label, "threads": self.device, "ms_per_frame": self.ms_per_frame,
            "mrays_per_s": self.mrays_per_s, "lookups_per_ray": self.lookups_per_ray,
            "mean_abs_bias": self.accuracy.map(|v| v.0), "mean_std": self.accuracy.map(|v| v.1),
        })
    }
}

/// One integrator at one thread count of the scaling table.
#[derive(Clone, Debug)]
pub struct ScalingRow {
    pub integrator: String,
    pub threads: usize,
    /// Median, smallest and largest ms per frame over the rounds.
    pub ms_median: f64,
    pub ms_min: f64,
    pub ms_max: f64,
    /// Median over the rounds of the speed-up over the first thread count.
    pub speedup: f64,
}

/// What a bench reports while it runs.
pub enum BenchEvent<'a> {
    /// What it is doing now (building the cloud, measuring accuracy).
    Note(String),
    /// The timings begin: the rows follow.
    Timing,
    Estimator(&'a EstimatorRow),
    Scaling(&'a ScalingRow),
}

/// The CPU's worker pool of `threads` workers (all cores when `None`).
fn pool(threads: Option<usize>) -> Result<Renderer, Error> {
    Renderer::cpu(threads_or_all(threads)?)
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

fn cloud_scene(size: u32, resolution: u32, scale: f32, frames: u32) -> Result<Scene, Error> {
    let text = cloud_text(size, resolution, scale, frames);
    Ok(Scene::build(
        parse_scene(&text, "bench scene", &[])?,
        Path::new("."),
    )?)
}

/// The estimators of `spec` (all when it names none), each with the label
/// its rows carry.
fn estimators(spec: &BenchSpec) -> Result<Vec<(Estimator, String)>, Error> {
    if spec.estimators.is_empty() {
        return Ok(Estimator::all()
            .into_iter()
            .map(|e| (e, e.name().to_string()))
            .collect());
    }
    spec.estimators
        .iter()
        .map(|n| Ok((Estimator::parse_spec(n).map_err(Error::invalid)?, n.clone())))
        .collect()
}

/// The GPU when `spec.devices` names it.
fn open_gpu(spec: &BenchSpec) -> Result<Option<Gpu>, Error> {
    if let Some(d) = spec.devices.iter().find(|d| *d != "cpu" && *d != "gpu") {
        return Err(Error::invalid(format!("--device: `{d}` is not cpu or gpu")));
    }
    if !spec.devices.iter().any(|d| d == "gpu") {
        return Ok(None);
    }
    Gpu::new()
        .map(Some)
        .map_err(|e| Error::runtime(format!("--device gpu: {e}")))
}

/// Every estimator of `spec` on every device of it: one row each, reported
/// as it is measured and returned in order.
pub fn bench_estimators(
    spec: &BenchSpec,
    report: &mut dyn FnMut(BenchEvent),
) -> Result<Vec<EstimatorRow>, Error> {
    let estimators = estimators(spec)?;
    report(BenchEvent::Note(format!(
        "building a {}³ cloud ...",
        spec.resolution
    )));
    let mut scene = cloud_scene(spec.size, spec.resolution, spec.sigma_t_scale, spec.frames)?;
    let accuracy = accuracy(spec, &scene, &estimators, report)?;
    let gpu = open_gpu(spec)?;
    if let Some(g) = &gpu {
        report(BenchEvent::Note(format!("GPU: {}", g.describe())));
    }
    // (backend, threads): the CPU at each thread count, then the GPU.
    let mut runs: Vec<(Backend, usize)> = Vec::new();
    if spec.devices.iter().any(|d| d == "cpu") {
        runs.extend(spec.threads.iter().map(|&t| (Backend::Cpu, t)));
    }
    if let Some(g) = &gpu {
        runs.push((Backend::Gpu(g), 1));
    }
    report(BenchEvent::Timing);
    let mut rows = Vec::new();
    for (backend, threads) in runs {
        let pool = pool(Some(threads))?;
        for ((e, label), &accuracy) in estimators.iter().zip(&accuracy) {
            scene.integrator = IntegratorKind::Transmittance(Transmittance {
                estimator: *e,
                background: fogbank_math::Vec3::ONE,
            });
            let (ms_per_frame, mrays_per_s, lookups_per_ray) =
                time_frames(spec, &scene, backend, &pool)?;
            let row = EstimatorRow {
                label: label.clone(),
                device: match backend {
                    Backend::Cpu => threads.to_string(),
                    Backend::Gpu(_) => backend.name().to_string(),
                },
                ms_per_frame,
                mrays_per_s,
                lookups_per_ray,
                accuracy,
            };
            report(BenchEvent::Estimator(&row));
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Mean |bias| and std of each estimator over `stats_frames` frames at
/// `stats_size`² against the exact transmittance (none with size 0).
fn accuracy(
    spec: &BenchSpec,
    scene: &Scene,
    estimators: &[(Estimator, String)],
    report: &mut dyn FnMut(BenchEvent),
) -> Result<Vec<Option<(f64, f64)>>, Error> {
    if spec.stats_size == 0 {
        return Ok(vec![None; estimators.len()]);
    }
    let mut small = cloud_scene(spec.stats_size, spec.resolution, spec.sigma_t_scale, 1)?;
    small.media = scene.media.clone();
    let pool = pool(spec.threads.iter().copied().max())?;
    Ok(estimators
        .iter()
        .map(|&(e, _)| {
            report(BenchEvent::Note(format!(
                "accuracy of {} over {} frames at {}² ...",
                e.name(),
                spec.stats_frames,
                spec.stats_size
            )));
            let exact = Some(Estimator::AnalyticTrilinear(AnalyticTrilinear));
            let s = pool
                .install(|| transmittance_stats(&small, e, exact, spec.stats_frames, 3))
                .summary();
            Some((s.mean_abs_bias, s.mean_std))
        })
        .collect())
}

/// (ms per frame, Mrays/s, lookups per ray) of `spec.frames` frames of
/// `scene` on `backend`, a GPU after one untimed frame of compilation and
/// upload.
fn time_frames(
    spec: &BenchSpec,
    scene: &Scene,
    backend: Backend,
    pool: &Renderer,
) -> Result<(f64, f64, f64), Error> {
    let opts = RenderOptions::new(spec.frames, 1);
    if let Backend::Gpu(_) = backend {
        let warm = RenderOptions {
            spp: 1,
            ..opts.clone()
        };
        backend
            .render(scene, &warm, &Progress::default())
            .map_err(Error::runtime)?;
    }
    let r = pool
        .install(|| backend.render(scene, &opts, &Progress::default()))
        .map_err(Error::runtime)?;
    let rays = (spec.size as u64 * spec.size as u64 * spec.frames as u64) as f64;
    Ok((
        r.seconds * 1000.0 / spec.frames as f64,
        rays / r.seconds / 1e6,
        r.film.lookups as f64 / rays,
    ))
}

/// The thread-scaling table: each integrator of `spec` on the cloud lit by
/// a sky and a sun (point lights for `point_mis` and `ament`) at each
/// thread count, ms per frame and the speed-up over the first count. With
/// `repeat` N > 1: one untimed warm-up render per thread count, then N
/// rounds, each timing every thread count in turn; a row gives the median
/// ms per frame, its range, and the median of the rounds' speed-ups
/// (pairing each round's timings keeps the ratio meaningful on a machine
/// whose speed drifts).
pub fn integrator_scaling(
    spec: &BenchSpec,
    report: &mut dyn FnMut(BenchEvent),
) -> Result<Vec<ScalingRow>, Error> {
    let cloud = cloud_text(spec.size, spec.resolution, spec.sigma_t_scale, spec.frames);
    let sky_and_sun = "[[lights]]\ntype = \"constant\"\nradiance = [0.55, 0.7, 1.0]\n\
                       [[lights]]\ntype = \"directional\"\ndirection = [-0.4, -0.8, -0.3]\nirradiance = [3.0, 2.9, 2.7]\n";
    // point_mis is the jackknife paper's point-light integrator; ament takes point lights.
    let points =
        "[[lights]]\ntype = \"point\"\nposition = [0.3, 0.2, 0.1]\nintensity = [1.0, 0.85, 0.7]\n";
    let rounds = spec.repeat.max(1) as usize;
    let mut rows = Vec::new();
    for name in &spec.integrators {
        let lights = if name == "point_mis" || name == "ament" {
            points
        } else {
            sky_and_sun
        };
        let set = [format!("integrator.type={name}")];
        let desc = parse_scene(&(cloud.clone() + lights), "bench scene", &set)?;
        let scene = Scene::build(desc, Path::new("."))?;
        let pools = spec
            .threads
            .iter()
            .map(|&t| pool(Some(t)))
            .collect::<Result<Vec<_>, _>>()?;
        let opts = RenderOptions::new(spec.frames, 1);
        let time = |pool: &Renderer| {
            let r = pool.install(|| fogbank_render::render(&scene, &opts, &Progress::default()));
            r.seconds * 1000.0 / spec.frames as f64
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
        for (k, &threads) in spec.threads.iter().enumerate() {
            let mine: Vec<f64> = ms.iter().map(|r| r[k]).collect();
            let speedup: Vec<f64> = ms.iter().map(|r| r[0] / r[k]).collect();
            let row = ScalingRow {
                integrator: name.clone(),
                threads,
                ms_min: mine.iter().cloned().fold(f64::INFINITY, f64::min),
                ms_max: mine.iter().cloned().fold(0.0, f64::max),
                ms_median: median(mine),
                speedup: median(speedup),
            };
            report(BenchEvent::Scaling(&row));
            rows.push(row);
        }
    }
    Ok(rows)
}

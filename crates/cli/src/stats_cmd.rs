//! `fogbank stats`: per-pixel mean, single-frame std and bias of an
//! estimator over K independent 1-spp frames (streamed: memory does not
//! grow with K), as EXR, false-colour maps and `summary.json`.

use crate::common::CliResult;
use crate::run_args::RunArgs;
use clap::Args;
use fogbank::load_scene_or;
use fogbank::study::FrameStats;
use fogbank::study::{write_stats, StatsJob, StatsReference};
use fogbank::Renderer;
use fogbank::TRANSMITTANCE_SCENE;
use std::path::PathBuf;

#[derive(Args)]
pub struct StatsArgs {
    /// Scene file: fogbank TOML (`.toml`), Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`); the cumulus's transmittance view (`scenes/transmittance.toml`) when omitted.
    pub scene: Option<PathBuf>,
    /// Estimator to measure (sets `integrator.estimator`; options via --set).
    #[arg(long)]
    pub estimator: Option<String>,
    /// Independent 1-spp frames.
    #[arg(long, default_value_t = 1024)]
    pub runs: u32,
    /// Exact estimator for the reference (e.g. analytic_trilinear).
    #[arg(long, conflicts_with = "reference")]
    pub reference_estimator: Option<String>,
    /// Reference image (EXR or PNG) of the same size, rendered through pixel
    /// centres (`--set render.pixel_jitter=false`).
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "stats")]
    pub out: PathBuf,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub shard: crate::shard_args::ShardArgs,
}

pub fn run(a: StatsArgs) -> CliResult {
    let mut overrides = a.run.set.clone();
    if let Some(e) = &a.estimator {
        overrides.push(format!("integrator.estimator={e}"));
    }
    let scene = load_scene_or(a.scene.as_deref(), TRANSMITTANCE_SCENE, &overrides)?;
    let reference = match (&a.reference_estimator, &a.reference) {
        (Some(n), _) => Some(StatsReference::exact(n)?),
        (None, Some(p)) => Some(StatsReference::Image(p.clone())),
        (None, None) => None,
    };
    let job = StatsJob {
        runs: a.runs,
        seed: a.run.seed,
        reference,
    };
    job.check()?;
    let shard = a.shard.get()?;
    if let Some(s) = shard {
        job.check_shard(s, a.run.device.device())?;
    }
    let renderer = Renderer::new(a.run.device.device(), a.run.threads)?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    if let Some(shard) = shard {
        let (path, seconds) = job.run_shard(&renderer, &scene, shard, &a.out)?;
        let piece = shard.piece(a.runs);
        eprintln!(
            "shard {} ({}): {seconds:.2} s; wrote {}",
            shard.label(),
            piece.describe(),
            path.display()
        );
        return Ok(());
    }
    eprintln!(
        "{} frames of {} at {}×{} ...",
        a.runs,
        scene.integrator.estimator_name(),
        scene.camera.width,
        scene.camera.height
    );
    let st = job.run(&renderer, &scene)?;
    let json = job.summary(&scene, &renderer, &st);
    write_outputs(&st, scene.integrator.estimator_name(), &a.out, &json)
}

/// Writes `stats.exr`, the false-colour maps and `summary.json` into
/// `out` (`fogbank::study::write_stats`), and prints the summary.
pub fn write_outputs(
    st: &FrameStats,
    estimator: &str,
    out: &std::path::Path,
    json: &serde_json::Value,
) -> CliResult {
    write_stats(st, estimator, out, json)?;
    println!("{}", serde_json::to_string_pretty(json)?);
    Ok(())
}

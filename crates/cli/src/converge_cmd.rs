//! `fogbank converge`: equal-time MSE-versus-time curves of several
//! estimators on one scene, measured in one run, as CSV (and plots).

use crate::common::CliResult;
use crate::run_args::RunArgs;
use clap::Args;
use fogbank::load_scene_or;
use fogbank::study::time_to_reach;
use fogbank::study::{write_curves, ConvergeJob};
use fogbank::TRANSMITTANCE_SCENE;
use fogbank::{Renderer, Scene};
use std::path::PathBuf;

#[derive(Args)]
pub struct ConvergeArgs {
    /// Scene file: fogbank TOML (`.toml`), Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`); the cumulus's transmittance view (`scenes/transmittance.toml`) when omitted.
    pub scene: Option<PathBuf>,
    /// Estimators to compare, comma separated (options via --set apply to all).
    #[arg(long, value_delimiter = ',', required = true)]
    pub estimators: Vec<String>,
    /// Render time per estimator in seconds.
    #[arg(long, default_value_t = 10.0)]
    pub seconds: f64,
    /// Exact estimator for the reference (primary rays then go through pixel centres).
    #[arg(long, default_value = "analytic_trilinear")]
    pub reference_estimator: String,
    /// Output folder.
    #[arg(long, default_value = "converge")]
    pub out: PathBuf,
    #[command(flatten)]
    pub run: RunArgs,
}

pub fn run(a: ConvergeArgs) -> CliResult {
    let job = ConvergeJob {
        estimators: a.estimators.clone(),
        seconds: a.seconds,
        reference: a.reference_estimator.clone(),
        seed: a.run.seed,
    };
    job.check()?;
    let renderer = Renderer::new(a.run.device.device(), a.run.threads)?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let overrides = ConvergeJob::overrides(&a.run.set);
    let load = |extra: &[String]| -> Result<Scene, fogbank::Error> {
        let o: Vec<String> = overrides.iter().chain(extra).cloned().collect();
        Ok(load_scene_or(a.scene.as_deref(), TRANSMITTANCE_SCENE, &o)?)
    };
    let curves = job.run(&renderer, &load, &mut |name| {
        eprintln!("{name}: {} s ...", a.seconds)
    })?;
    write_curves(&curves, &a.out)?;
    // Equal-error comparison: the time each needs to reach the worst final MSE.
    let target = curves
        .iter()
        .filter_map(|c| c.points.last().map(|p| p.mse))
        .fold(0.0, f64::max);
    println!("| estimator | spp | final MSE | seconds to MSE {target:.3e} |");
    println!("|---|---:|---:|---:|");
    for c in &curves {
        let last = c.points.last();
        println!(
            "| {} | {} | {:.3e} | {} |",
            c.label,
            last.map_or(0, |p| p.spp),
            last.map_or(f64::NAN, |p| p.mse),
            time_to_reach(&c.points, target).map_or("–".to_string(), |t| format!("{t:.3}"))
        );
    }
    Ok(())
}

//! `fogbank converge`: equal-time MSE-versus-time curves of several
//! estimators on one scene, measured in one run, as CSV (and plots).

use crate::common::CliResult;
use crate::run_args::RunArgs;
use clap::Args;
use fogbank_estimators::Estimator;
use fogbank_eval::converge::{convergence, time_to_reach, write_csv, Curve};
use fogbank_eval::{exact_reference, Backend};
use fogbank_render::{load_scene_or, TRANSMITTANCE_SCENE};
use std::path::PathBuf;

#[derive(Args)]
pub struct ConvergeArgs {
    /// Scene file (TOML); the cumulus's transmittance view (`scenes/transmittance.toml`) when omitted.
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
    if !(a.seconds > 0.0 && a.seconds.is_finite()) {
        return Err("--seconds must be positive".into());
    }
    let mut overrides = a.run.set.clone();
    overrides.push("render.pixel_jitter=false".into());
    let pool = a.run.pool()?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let reference_estimator = Estimator::parse(&a.reference_estimator)
        .filter(|e| matches!(e, Estimator::AnalyticTrilinear | Estimator::RegularTracking))
        .ok_or_else(|| {
            format!(
                "--reference-estimator must be analytic_trilinear or regular_tracking, not `{}`",
                a.reference_estimator
            )
        })?;
    let gpu = a.run.gpu()?;
    let backend = Backend::from(gpu.as_ref());
    let base = load_scene_or(a.scene.as_deref(), TRANSMITTANCE_SCENE, &overrides)?;
    let reference = pool.install(|| exact_reference(&base, reference_estimator));
    let mut curves = Vec::new();
    for name in &a.estimators {
        let mut o = overrides.clone();
        o.push(format!("integrator.estimator={name}"));
        let scene = load_scene_or(a.scene.as_deref(), TRANSMITTANCE_SCENE, &o)?;
        eprintln!("{name}: {} s ...", a.seconds);
        let points = pool
            .install(|| convergence(backend, &scene, a.seconds, &reference, a.run.seed))
            .map_err(|e| format!("--device {}: {e}", backend.name()))?;
        curves.push(Curve {
            label: name.clone(),
            points,
        });
    }
    write_csv(&a.out.join("converge.csv"), &curves)?;
    fogbank_eval::converge::plot(&curves, "equal-time convergence", &a.out.join("converge"))?;
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

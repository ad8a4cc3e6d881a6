//! `fogbank experiment NAME`: runs one of the papers' experiments (or one
//! of the engine's measurements) and writes its CSV, plots and summary.

use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ExperimentArgs {
    #[arg(help = name_help())]
    pub name: String,
    /// Output directory (default: experiments/NAME).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Trials (Monte Carlo realisations) overriding the experiment's default.
    #[arg(long)]
    pub trials: Option<u64>,
}

pub fn run(a: ExperimentArgs) -> crate::common::CliResult {
    let (name, _) = fogbank_experiments::current_name(&a.name);
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("experiments").join(&name));
    let report = fogbank_experiments::run(&a.name, &out, a.trials)?;
    println!("{}", report.summary);
    println!();
    for f in &report.files {
        println!("wrote {}", f.display());
    }
    println!("{} took {:.1} s", report.name, report.seconds);
    Ok(())
}

/// The help of NAME, generated from the experiments `fogbank_eval` runs so
/// that it lists every one.
fn name_help() -> String {
    let names = fogbank_experiments::names();
    let (last, rest) = names.split_last().expect("at least one experiment");
    format!(
        "Experiment: {} or {last} (jackknife-fig12: --trials is the reference's spp)",
        rest.join(", ")
    )
}

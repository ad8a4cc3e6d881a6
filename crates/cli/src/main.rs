//! `fogbank`: the one binary. Subcommands live one per file.

mod bench_cmd;
mod common;
mod compare_cmd;
mod converge_cmd;
mod convert_cmd;
mod experiment_cmd;
mod export_cmd;
mod frames_cmd;
mod info_cmd;
mod integrators_cmd;
mod merge_cmd;
mod render_cmd;
mod report_cmd;
mod run_args;
mod shard_args;
mod stats_cmd;
mod view_cmd;
mod volume_write_args;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "fogbank",
    version,
    about = "Monte Carlo rendering of heterogeneous participating media"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene (the built-in default scene when none is given).
    Render(render_cmd::RenderArgs),
    /// Add up the partial results (.fbpart) of a sharded render or stats run (`--shard I/N`).
    Merge(merge_cmd::MergeArgs),
    /// Describe a volume file (.vdb, .nvdb, .vol, .nii, .nii.gz, .hdr, .nrrd, .nhdr, .raw).
    Info(info_cmd::InfoArgs),
    /// Write a scene medium's density (or temperature) grid as .vdb or .nvdb.
    Export(export_cmd::ExportArgs),
    /// Convert a scene (pbrt-v4, Mitsuba XML, TOML → TOML or Mitsuba XML) or a volume (→ .vdb/.nvdb).
    Convert(convert_cmd::ConvertArgs),
    /// List the transmittance estimators.
    Estimators,
    /// List the integrators and their parameters (`integrator.type` and keys).
    Integrators(integrators_cmd::IntegratorsArgs),
    /// Primary-ray transmittance throughput per estimator.
    Bench(bench_cmd::BenchArgs),
    /// Run one of the papers' experiments (jackknife, ReSTIR, visopt, pins; NAME's help lists them).
    Experiment(experiment_cmd::ExperimentArgs),
    /// Compare two images (rmse, relmse, smape, flip, ztest).
    Compare(compare_cmd::CompareArgs),
    /// Per-pixel mean, std and bias of an estimator over independent frames.
    Stats(stats_cmd::StatsArgs),
    /// Equal-time MSE-versus-time curves of several estimators.
    Converge(converge_cmd::ConvergeArgs),
    /// Gather a folder of outputs into one offline HTML page.
    Report(report_cmd::ReportArgs),
    /// Open the interactive viewer (progressive rendering in a window).
    View(view_cmd::ViewArgs),
}

/// A reader that closes the pipe early (`fogbank info x.vdb | head`) ends
/// the program quietly, as it does other Unix tools: Rust ignores SIGPIPE,
/// so without this `println!` panics on the broken pipe.
#[cfg(unix)]
fn quiet_on_closed_pipes() {
    // SAFETY: restoring a signal's default disposition at startup, before
    // any thread exists, has no preconditions.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn quiet_on_closed_pipes() {}

fn main() -> ExitCode {
    quiet_on_closed_pipes();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(a) => render_cmd::run(a),
        Command::Merge(a) => merge_cmd::run(a),
        Command::Info(a) => info_cmd::run(a),
        Command::Export(a) => export_cmd::run(a),
        Command::Convert(a) => convert_cmd::run(a),
        Command::Estimators => {
            for e in fogbank::Estimator::all() {
                let kind = if e.biased() { "biased" } else { "unbiased" };
                println!("{:<26} {:<8} {}", e.name(), kind, e.description());
                if !e.options_help().is_empty() {
                    println!("{:<35} options: {}", "", e.options_help());
                }
            }
            Ok(())
        }
        Command::Integrators(a) => integrators_cmd::run(a),
        Command::Bench(a) => bench_cmd::run(a),
        Command::Experiment(a) => experiment_cmd::run(a),
        Command::Compare(a) => compare_cmd::run(a),
        Command::Stats(a) => stats_cmd::run(a),
        Command::Converge(a) => converge_cmd::run(a),
        Command::Report(a) => report_cmd::run(a),
        Command::View(a) => view_cmd::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

//! The papers' experiments, one folder per paper: each experiment
//! reproduces one figure or table of its paper with the project's own
//! estimators and renderers (synthetic data or shipped scenes, no
//! downloads unless stated), writes CSV, plots (SVG + PNG) and a
//! `summary.md` stating the finding with numbers. Every run is
//! deterministic (fixed seeds, chunked parallel streams) and its trial
//! count can be overridden.
//!
//! - [`peters2025_jackknife`]: C. Peters, *Jackknife Transmittance and MIS
//!   Weight Estimation*, ACM TOG 44(6), 2025 (Peters 2025: `jackknife-fig1`
//!   … `jackknife-fig14`, `jackknife-table1`);
//! - [`lin2021_restir`]: D. Lin, C. Wyman, C. Yuksel, *Fast Volume Rendering
//!   with Spatiotemporal Reservoir Resampling*, ACM TOG 40(6), 2021
//!   (Lin et al. 2021: `restir-*`);
//! - [`lerzer2025_visopt`]: N. Lerzer, C. Dachsbacher, *View-Dependent
//!   Visibility Optimization for Monte Carlo Volume Visualization*, CGF 2025
//!   (Lerzer and Dachsbacher 2025: `visopt-*`);
//! - [`hansen2025_pins`]: S. Hansen, *Pin Transmittance Sampling*, master
//!   thesis, KIT 2025 (Hansen 2025: `pins-*`);
//! - [`engine`]: measurements of fogbank's own machinery that reproduce no
//!   paper (`bvh-perf`, `light-bvh`);
//! - [`harness`]: what the experiments share — the output writer,
//!   deterministic chunked trials, the frame-rendering protocol (references,
//!   MSE, equal-time races), GPU timing, scene edits and curve fits.
//!
//! `EXPERIMENTS` below is the one list of the names `fogbank experiment`
//! takes; each name maps to the `run` of one file in a folder above.

pub mod denoise;
pub mod engine;
pub mod hansen2025_pins;
pub mod harness;
pub mod lerzer2025_visopt;
pub mod lin2021_restir;
pub mod peters2025_jackknife;

use std::path::{Path, PathBuf};
use std::time::Instant;

pub use harness::Writer;

/// What a run produced.
#[derive(Clone, Debug)]
pub struct ExperimentReport {
    pub name: String,
    /// Every file written, in order.
    pub files: Vec<PathBuf>,
    /// The finding, as written to `summary.md`.
    pub summary: String,
    pub seconds: f64,
}

/// How an experiment runs: into a writer, with an optional trial count,
/// returning the finding that `summary.md` states.
type Run = fn(&mut Writer, Option<u64>) -> Result<String, String>;

/// Every experiment, by the name `fogbank experiment` takes, listed once.
const EXPERIMENTS: &[(&str, Run)] = &[
    ("jackknife-fig1", peters2025_jackknife::fig1::run),
    ("jackknife-fig2", peters2025_jackknife::fig2::run),
    ("jackknife-fig3", peters2025_jackknife::fig3::run),
    ("jackknife-fig4", |w, trials| {
        peters2025_jackknife::fig4::run(w, trials, peters2025_jackknife::fig4::Variant::Smooth)
    }),
    ("jackknife-fig5", peters2025_jackknife::fig5::run),
    ("jackknife-fig6", |w, trials| {
        peters2025_jackknife::fig4::run(w, trials, peters2025_jackknife::fig4::Variant::Sparse)
    }),
    ("jackknife-fig7", peters2025_jackknife::fig7::run),
    ("jackknife-fig12", peters2025_jackknife::fig12::run),
    ("jackknife-fig13", peters2025_jackknife::fig13::run),
    ("jackknife-table1", peters2025_jackknife::table1::run),
    ("jackknife-fig14", peters2025_jackknife::fig14::run),
    ("restir-equal-time", lin2021_restir::equal_time::run),
    ("restir-surfaces", lin2021_restir::surfaces::run),
    ("restir-ablation", lin2021_restir::ablation::run),
    ("restir-dynamic", lin2021_restir::dynamic::run),
    ("restir-bias", lin2021_restir::bias::run),
    ("restir-gpu-frame-time", lin2021_restir::gpu_frame_time::run),
    ("pins-stream", hansen2025_pins::stream::run),
    ("pins-surfaces", hansen2025_pins::surfaces::run),
    ("pins-fig3-4", hansen2025_pins::fig3_4::run),
    ("pins-instances", hansen2025_pins::instances::run),
    ("pins-memory", hansen2025_pins::memory::run),
    ("pins-ablation", hansen2025_pins::ablation::run),
    ("pins-bias", hansen2025_pins::bias::run),
    ("pins-boundary", hansen2025_pins::boundary::run),
    ("pins-runtime", hansen2025_pins::runtime::run),
    ("pins-gpu-runtime", hansen2025_pins::runtime::run_gpu),
    ("pins-convergence", hansen2025_pins::convergence::run),
    ("visopt-fig2", lerzer2025_visopt::fig2::run),
    ("visopt-fig7", lerzer2025_visopt::fig7::run),
    ("visopt-overhead", lerzer2025_visopt::overhead::run),
    ("visopt-head", lerzer2025_visopt::head::run),
    ("visopt-pre", lerzer2025_visopt::pre::run),
    ("visopt-equal-time", lerzer2025_visopt::equal_time::run),
    ("visopt-teaser", lerzer2025_visopt::teaser::run),
    ("visopt-denoise", lerzer2025_visopt::denoise::run),
    (
        "visopt-gpu-frame-time",
        lerzer2025_visopt::gpu_frame_time::run,
    ),
    ("bvh-perf", engine::bvh_perf::run),
    ("light-bvh", engine::light_bvh::run),
];

/// The experiment names `run` accepts.
pub fn names() -> Vec<&'static str> {
    EXPERIMENTS.iter().map(|(n, _)| *n).collect()
}

/// The name `name` has now: the jackknife paper's experiments were `fig1`
/// … `table1` before every experiment's name began with its method's. The
/// old names are accepted, with a notice, for one release.
pub fn current_name(name: &str) -> (String, Option<String>) {
    let old = name.starts_with("fig") || name == "table1";
    let new = format!("jackknife-{name}");
    if old && names().contains(&new.as_str()) {
        let notice =
            format!("experiment `{name}` is now `{new}`; the old name goes in the next release");
        (new, Some(notice))
    } else {
        (name.to_string(), None)
    }
}

/// Runs experiment `name` into directory `out` (created if missing) with
/// `trials` overriding its default trial count.
pub fn run(name: &str, out: &Path, trials: Option<u64>) -> Result<ExperimentReport, String> {
    if trials == Some(0) {
        return Err("--trials must be at least 1".into());
    }
    let (name, notice) = current_name(name);
    if let Some(notice) = notice {
        eprintln!("notice: {notice}");
    }
    let name = name.as_str();
    let Some((_, experiment)) = EXPERIMENTS.iter().find(|(n, _)| *n == name) else {
        return Err(format!(
            "unknown experiment '{name}' (known: {})",
            names().join(", ")
        ));
    };
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let start = Instant::now();
    let mut w = Writer {
        out: out.to_path_buf(),
        files: Vec::new(),
    };
    let summary = experiment(&mut w, trials)?;
    let seconds = start.elapsed().as_secs_f64();
    let command = match trials {
        Some(t) => format!("fogbank experiment {name} --trials {t}"),
        None => format!("fogbank experiment {name}"),
    };
    let md = format!("# {name}\n\n{summary}\n\nMade by `{command}` in {seconds:.1} s.\n");
    w.text("summary.md", &md)?;
    Ok(ExperimentReport {
        name: name.to_string(),
        files: w.files,
        summary,
        seconds,
    })
}

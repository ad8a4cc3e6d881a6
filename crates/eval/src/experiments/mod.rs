//! The seeds' experiments (seed 000's one-dimensional studies; seed 002's
//! `restir-*` studies on rendered frames): each reproduces one figure or
//! table of the paper on synthetic data with the project's own estimators,
//! writes CSV, plots (SVG + PNG) and a `summary.md` stating the finding with
//! numbers. Every run is deterministic (fixed seeds, chunked parallel
//! streams) and its trial count can be overridden.

pub mod bvh_perf;
pub mod distributions;
pub mod fig1;
pub mod fig12;
pub mod fig13;
pub mod fig14;
pub mod fig2;
pub mod fig3;
pub mod fig4;
pub mod fig5;
pub mod fig7;
mod fit;
pub mod light_bvh;
pub mod pins_ablation;
pub mod pins_bias;
pub mod pins_boundary;
pub mod pins_convergence;
pub mod pins_fig3_4;
pub mod pins_instances;
pub mod pins_memory;
pub mod pins_runtime;
pub mod pins_stream;
pub mod pins_surfaces;
pub mod profile;
pub mod restir_ablation;
pub mod restir_bias;
pub mod restir_dynamic;
pub mod restir_equal_time;
pub mod restir_gpu_frame_time;
pub mod restir_protocol;
pub mod restir_race;
pub mod restir_scenes;
pub mod restir_surfaces;
mod scene_edit;
pub mod table1;
pub mod trials;
pub mod visopt_denoise;
pub mod visopt_equal_time;
pub mod visopt_fig2;
pub mod visopt_fig7;
pub mod visopt_gpu_frame_time;
pub mod visopt_head;
pub mod visopt_overhead;
pub mod visopt_pre;
pub mod visopt_teaser;
mod writer;

use std::path::{Path, PathBuf};
use std::time::Instant;

pub use fit::log_log_fit;
pub use writer::Writer;

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
    ("fig1", fig1::run),
    ("fig2", fig2::run),
    ("fig3", fig3::run),
    ("fig4", |w, trials| {
        fig4::run(w, trials, fig4::Variant::Smooth)
    }),
    ("fig5", fig5::run),
    ("fig6", |w, trials| {
        fig4::run(w, trials, fig4::Variant::Sparse)
    }),
    ("fig7", fig7::run),
    ("fig12", fig12::run),
    ("fig13", fig13::run),
    ("table1", table1::run),
    ("fig14", fig14::run),
    ("restir-equal-time", restir_equal_time::run),
    ("restir-surfaces", restir_surfaces::run),
    ("restir-ablation", restir_ablation::run),
    ("restir-dynamic", restir_dynamic::run),
    ("restir-bias", restir_bias::run),
    ("restir-gpu-frame-time", restir_gpu_frame_time::run),
    ("pins-stream", pins_stream::run),
    ("pins-surfaces", pins_surfaces::run),
    ("pins-fig3-4", pins_fig3_4::run),
    ("pins-instances", pins_instances::run),
    ("pins-memory", pins_memory::run),
    ("pins-ablation", pins_ablation::run),
    ("pins-bias", pins_bias::run),
    ("pins-boundary", pins_boundary::run),
    ("pins-runtime", pins_runtime::run),
    ("pins-gpu-runtime", pins_runtime::run_gpu),
    ("pins-convergence", pins_convergence::run),
    ("visopt-fig2", visopt_fig2::run),
    ("visopt-fig7", visopt_fig7::run),
    ("visopt-overhead", visopt_overhead::run),
    ("visopt-head", visopt_head::run),
    ("visopt-pre", visopt_pre::run),
    ("visopt-equal-time", visopt_equal_time::run),
    ("visopt-teaser", visopt_teaser::run),
    ("visopt-denoise", visopt_denoise::run),
    ("visopt-gpu-frame-time", visopt_gpu_frame_time::run),
    ("bvh-perf", bvh_perf::run),
    ("light-bvh", light_bvh::run),
];

/// The experiment names `run` accepts.
pub fn names() -> Vec<&'static str> {
    EXPERIMENTS.iter().map(|(n, _)| *n).collect()
}

/// Runs experiment `name` into directory `out` (created if missing) with
/// `trials` overriding its default trial count.
pub fn run(name: &str, out: &Path, trials: Option<u64>) -> Result<ExperimentReport, String> {
    if trials == Some(0) {
        return Err("--trials must be at least 1".into());
    }
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

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

/// The experiment names `run` accepts.
pub fn names() -> &'static [&'static str] {
    &[
        "fig1",
        "fig2",
        "fig3",
        "fig4",
        "fig5",
        "fig6",
        "fig7",
        "fig12",
        "fig13",
        "table1",
        "fig14",
        "restir-equal-time",
        "restir-surfaces",
        "restir-ablation",
        "restir-dynamic",
        "restir-bias",
        "restir-gpu-frame-time",
        "pins-stream",
        "pins-surfaces",
        "pins-fig3-4",
        "pins-instances",
        "pins-memory",
        "pins-ablation",
        "pins-bias",
        "pins-boundary",
        "pins-runtime",
        "pins-gpu-runtime",
        "pins-convergence",
        "visopt-fig2",
        "visopt-fig7",
        "visopt-overhead",
        "visopt-head",
        "visopt-pre",
        "visopt-equal-time",
        "visopt-teaser",
        "visopt-denoise",
        "visopt-gpu-frame-time",
        "bvh-perf",
        "light-bvh",
    ]
}

/// Runs experiment `name` into directory `out` (created if missing) with
/// `trials` overriding its default trial count.
pub fn run(name: &str, out: &Path, trials: Option<u64>) -> Result<ExperimentReport, String> {
    if trials == Some(0) {
        return Err("--trials must be at least 1".into());
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let start = Instant::now();
    let mut w = Writer {
        out: out.to_path_buf(),
        files: Vec::new(),
    };
    let summary = match name {
        "fig1" => fig1::run(&mut w, trials),
        "fig2" => fig2::run(&mut w, trials),
        "fig3" => fig3::run(&mut w, trials),
        "fig4" => fig4::run(&mut w, trials, fig4::Variant::Smooth),
        "fig6" => fig4::run(&mut w, trials, fig4::Variant::Sparse),
        "fig5" => fig5::run(&mut w, trials),
        "fig7" => fig7::run(&mut w, trials),
        "fig12" => fig12::run(&mut w, trials),
        "fig13" => fig13::run(&mut w, trials),
        "table1" => table1::run(&mut w, trials),
        "fig14" => fig14::run(&mut w, trials),
        "restir-equal-time" => restir_equal_time::run(&mut w, trials),
        "restir-surfaces" => restir_surfaces::run(&mut w, trials),
        "restir-ablation" => restir_ablation::run(&mut w, trials),
        "restir-dynamic" => restir_dynamic::run(&mut w, trials),
        "restir-bias" => restir_bias::run(&mut w, trials),
        "restir-gpu-frame-time" => restir_gpu_frame_time::run(&mut w, trials),
        "pins-stream" => pins_stream::run(&mut w, trials),
        "pins-surfaces" => pins_surfaces::run(&mut w, trials),
        "pins-fig3-4" => pins_fig3_4::run(&mut w, trials),
        "pins-instances" => pins_instances::run(&mut w, trials),
        "pins-memory" => pins_memory::run(&mut w, trials),
        "pins-ablation" => pins_ablation::run(&mut w, trials),
        "pins-bias" => pins_bias::run(&mut w, trials),
        "pins-boundary" => pins_boundary::run(&mut w, trials),
        "pins-runtime" => pins_runtime::run(&mut w, trials),
        "pins-gpu-runtime" => pins_runtime::run_gpu(&mut w, trials),
        "pins-convergence" => pins_convergence::run(&mut w, trials),
        "visopt-fig2" => visopt_fig2::run(&mut w, trials),
        "visopt-fig7" => visopt_fig7::run(&mut w, trials),
        "visopt-overhead" => visopt_overhead::run(&mut w, trials),
        "visopt-head" => visopt_head::run(&mut w, trials),
        "visopt-pre" => visopt_pre::run(&mut w, trials),
        "visopt-equal-time" => visopt_equal_time::run(&mut w, trials),
        "visopt-teaser" => visopt_teaser::run(&mut w, trials),
        "visopt-denoise" => visopt_denoise::run(&mut w, trials),
        "bvh-perf" => bvh_perf::run(&mut w, trials),
        "light-bvh" => light_bvh::run(&mut w, trials),
        "visopt-gpu-frame-time" => visopt_gpu_frame_time::run(&mut w, trials),
        _ => {
            return Err(format!(
                "unknown experiment '{name}' (known: {})",
                names().join(", ")
            ))
        }
    }?;
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

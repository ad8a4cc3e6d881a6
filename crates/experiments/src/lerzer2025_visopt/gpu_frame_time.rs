//! Lerzer and Dachsbacher 2025 Table 3 (and Fig. 1's frame times) on a GPU:
//! memory and device time per 10-spp frame at 800², 1600² and
//! 1920×1080 on the HEPTANE stand-in of `visopt-overhead` — plain DVR
//! (`optimise = false`), `visopt` with camera-ray lists only, full
//! single-scattering `visopt` (200-sample NEE lists) and the multiple-
//! scattering setting with every NEE optimised (Fig. 9's third), measured
//! side by side in one run. Memory: the camera lists' pool (built on the
//! CPU, 1 uniform + 3 adaptive passes of 64 samples, and uploaded) and the
//! NEE-list scratch (one 200-entry list per pixel of a band of rows, at
//! most `Gpu::scratch_budget`). `--trials` sets the measured frames
//! (default 4, after one warm-up frame). Needs timestamp queries; lavapipe
//! runs it, but its times say nothing about a GPU.

use super::overhead::heptane_standin_sized;
use crate::harness::timing::{clocked, gpu_warm_up, median};
use crate::harness::Writer;
use fogbank_gpu::Gpu;
use fogbank_render::integrators::visopt::VisOpt;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{Progress, RenderOptions, Scene};

/// The paper's frame: 10 samples per pixel (Table 3, Fig. 1).
const FRAME_SPP: u32 = 10;
const SIZES: [(u32, u32); 3] = [(800, 800), (1600, 1600), (1920, 1080)];

const METHODS: [(&str, &[&str]); 4] = [
    ("DVR", &["integrator.optimise=false"]),
    ("visopt, camera lists only", &["integrator.light_samples=0"]),
    ("visopt SS", &[]),
    (
        "visopt MS (every NEE optimised)",
        &["integrator.scattering=\"all\""],
    ),
];

/// Median device milliseconds per frame over `frames` frames after one
/// warm-up frame (single frames on an H100 varied up to 2.5×).
fn frame_ms(gpu: &Gpu, scene: &Scene, frames: u32) -> Result<f64, String> {
    gpu_warm_up(gpu, scene)?;
    let mut times = Vec::new();
    for f in 0..=frames {
        let opts = RenderOptions::new(FRAME_SPP, f);
        let r = fogbank_gpu::render::render(gpu, scene, &opts, &Progress::default())
            .map_err(|e| e.0)?;
        let ms = r
            .gpu_ms
            .ok_or_else(|| format!("{}: no kernel time", gpu.describe()))?;
        if f > 0 {
            times.push(ms);
        }
    }
    Ok(median(times))
}

/// The camera lists' pool, the NEE scratch and the CPU build time of the
/// lists at `(width, height)`: the Markdown table's cells and the CSV row.
fn list_memory(
    gpu: &Gpu,
    v: &VisOpt,
    scene: &Scene,
    (width, height): (u32, u32),
) -> (String, Vec<String>) {
    let (lists, build) = clocked(|| v.lists(&scene.world));
    let px = (width * height) as f64;
    let pool_mb = lists.memory_bytes() as f64 / 1e6;
    let scratch_mb =
        fogbank_gpu::visopt::scratch(gpu, width, height, v.params.light_samples).1 as f64 / 1e6;
    let memory = format!(
        "{pool_mb:.1} | {:.1} | {scratch_mb:.1} | {build:.2}",
        lists.pool.len() as f64 / px
    );
    let row = vec![
        format!("{width}x{height}"),
        "memory".into(),
        format!("{pool_mb:.3}"),
        format!("{:.3}", lists.pool.len() as f64 / px),
        format!("{scratch_mb:.3}"),
        format!("{build:.3}"),
    ];
    (memory, row)
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let gpu = Gpu::new().map_err(|e| e.0)?;
    run_on(&gpu, w, trials, &SIZES)
}

/// [`run`] on `gpu` at `sizes` (smaller ones for smoke tests).
pub fn run_on(
    gpu: &Gpu,
    w: &mut Writer,
    trials: Option<u64>,
    sizes: &[(u32, u32)],
) -> Result<String, String> {
    let frames = trials.unwrap_or(4).clamp(1, 1000) as u32;
    if !gpu.timestamps {
        return Err(format!("{}: no timestamp queries", gpu.describe()));
    }
    let (mut rows, mut table) = (Vec::new(), Vec::new());
    for &(width, height) in sizes {
        let mut times = Vec::new();
        let mut memory = String::new();
        for (name, extra) in METHODS {
            let mut set = vec!["integrator.type=\"visopt\""];
            set.extend_from_slice(extra);
            let scene = heptane_standin_sized(width, height, &set)?;
            let IntegratorKind::VisOpt(v) = &scene.integrator else {
                return Err("the stand-in's integrator is visopt".into());
            };
            if name == "visopt SS" {
                let (cells, row) = list_memory(gpu, v, &scene, (width, height));
                memory = cells;
                rows.push(row);
            } else {
                // Built outside the timed frames either way.
                v.lists(&scene.world);
            }
            let ms = frame_ms(gpu, &scene, frames)?;
            rows.push(vec![
                format!("{width}x{height}"),
                name.to_string(),
                format!("{ms:.4}"),
                String::new(),
                String::new(),
                String::new(),
            ]);
            times.push(ms);
        }
        table.push(format!(
            "| {width}×{height} | {memory} | {} |",
            times
                .iter()
                .map(|t| format!("{t:.1}"))
                .collect::<Vec<_>>()
                .join(" | ")
        ));
    }
    w.csv(
        "frame_time.csv",
        &[
            "size",
            "what",
            "ms_per_frame_or_pool_mb",
            "entries_per_pixel",
            "scratch_mb",
            "cpu_list_build_s",
        ],
        &rows,
    )?;
    Ok(format!(
        "Lerzer and Dachsbacher 2025 Table 3 on {}: device milliseconds per {FRAME_SPP}-spp frame (timestamp queries, median of \
         {frames} frames after one warm-up) on the HEPTANE stand-in (cloud 128³ in [−1, 1]³, two point \
         lights, dense core important); camera lists built on the CPU ({} threads) and uploaded, NEE lists \
         of 200 samples built on the device in a scratch of one list per pixel of a band of rows.\n\n\
         | size | camera-list pool MB | entries / pixel | NEE scratch MB | CPU list build s | DVR ms | \
         visopt camera lists only ms | visopt SS ms | visopt MS ms |\n|---|---|---|---|---|---|---|---|---|\n{}\n",
        gpu.describe(),
        rayon::current_num_threads(),
        table.join("\n")
    ))
}

#[cfg(test)]
mod smoke_test {
    use crate::harness::timing::timestamp_test_gpu;
    use crate::harness::Writer;

    /// The table is written end to end at a tiny size on whatever device
    /// there is (lavapipe in CI); the times mean nothing there.
    #[test]
    fn table_3_is_written() {
        let Some(gpu) = timestamp_test_gpu() else {
            return;
        };
        let mut w = Writer::temp("fogbank_visopt_t3");
        let summary = super::run_on(&gpu, &mut w, Some(1), &[(16, 12)]).unwrap();
        assert!(summary.contains("| 16×12 |"), "{summary}");
        let csv = std::fs::read_to_string(w.path("frame_time.csv")).unwrap();
        // Header, the memory row and one row per method.
        assert_eq!(csv.lines().count(), 2 + super::METHODS.len(), "{csv}");
        std::fs::remove_dir_all(&w.out).ok();
    }
}

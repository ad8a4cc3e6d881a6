//! Timing: wall-clock seconds of a piece of work, and device milliseconds
//! per sample on a GPU from timestamp queries, the median of several
//! renders after a warm-up, since a GPU's clocks and its neighbours make
//! single renders unreliable.

pub use super::clock::clocked;
use super::protocol::build;
pub use fogbank_eval::median::median;
use fogbank_render::{Progress, RenderOptions, Scene};

/// Device milliseconds per sample of `text` with `set`, `spp` samples: the
/// median of [`TIMED_RENDERS`] renders after [`gpu_warm_up`]. On an H100
/// single renders of the same setting differed up to 5× from run to run
/// (9.6 against 1.75 ms per spp), so one render is no timing.
pub fn gpu_ms_per_spp(
    gpu: &fogbank_gpu::Gpu,
    text: &str,
    set: &[String],
    spp: u32,
) -> Result<f64, String> {
    let scene = build(text, set)?;
    let render = |spp| -> Result<f64, String> {
        let opts = RenderOptions::new(spp, 1);
        let r = fogbank_gpu::render::render(gpu, &scene, &opts, &Progress::default())
            .map_err(|e| e.0)?;
        r.gpu_ms
            .ok_or_else(|| "the device has no timestamp queries".to_string())
    };
    gpu_warm_up(gpu, &scene)?;
    // A CPU device's times say nothing about a GPU: one render will do.
    let renders = if gpu.is_cpu() { 1 } else { TIMED_RENDERS };
    let times = (0..renders)
        .map(|_| render(spp))
        .collect::<Result<Vec<f64>, String>>()?;
    Ok(median(times) / spp as f64)
}

/// Keeps the device busy rendering `scene` for half a second of wall time
/// and discards the image. An idle H100 sits at 345 MHz and needs a while
/// of load to reach its 1980 MHz boost clock, so times taken right after CPU
/// work (scene building, pin gathering, visopt's camera lists) came out up
/// to 5× slow without this.
/// A CPU device (lavapipe) has no clocks to ramp up and is skipped.
pub fn gpu_warm_up(gpu: &fogbank_gpu::Gpu, scene: &Scene) -> Result<(), String> {
    if gpu.is_cpu() {
        return Ok(());
    }
    let opts = RenderOptions {
        spp: 1 << 20,
        seed: 0,
        time_budget: Some(std::time::Duration::from_millis(500)),
    };
    fogbank_gpu::render::render(gpu, scene, &opts, &Progress::default()).map_err(|e| e.0)?;
    Ok(())
}

/// How many renders [`gpu_ms_per_spp`] takes the median of.
pub const TIMED_RENDERS: usize = 5;

/// The test device (lavapipe in CI) if it has timestamp queries; `None`,
/// saying why, when there is none or it has no timestamps, and the GPU
/// smoke tests skip.
#[cfg(test)]
pub(crate) fn timestamp_test_gpu() -> Option<fogbank_gpu::Gpu> {
    let gpu = fogbank_gpu::test_gpu()?;
    if !gpu.timestamps {
        eprintln!("SKIPPED (no timestamp queries on {})", gpu.describe());
        return None;
    }
    Some(gpu)
}

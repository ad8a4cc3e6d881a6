//! What a render reports (`fogbank render --stats`, Python's
//! `Image.stats`): the integrator, the film's size, samples and mean, time,
//! threads and device, lookups per sample, dropped samples, memory.

use crate::renderer::{Rendered, Renderer};
use fogbank_render::integrators::shared::pin_params::GridPlan;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::Scene;
use serde_json::{json, Value};

/// Peak resident set size of this process (Linux `VmHWM`), 0 elsewhere.
pub fn peak_memory_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| {
                l.split_whitespace()
                    .nth(1)
                    .and_then(|kb| kb.parse::<u64>().ok())
                    .map(|kb| kb * 1024)
            })
        })
        .unwrap_or(0)
}

/// Lookups per pixel sample of `rendered`.
pub fn lookups_per_sample(rendered: &Rendered) -> f64 {
    let samples = rendered.film.total_samples();
    if samples > 0 {
        rendered.film.lookups as f64 / samples as f64
    } else {
        0.0
    }
}

/// The statistics of a render of `scene` asked for `spp` samples per pixel
/// (`u32::MAX`: until a time budget) with `seed`; `bad_pixels` is what
/// writing the images reported.
pub fn render_stats(
    scene: &Scene,
    renderer: &Renderer,
    rendered: &Rendered,
    spp: u32,
    seed: u32,
    bad_pixels: usize,
) -> Value {
    let film = &rendered.film;
    json!({
        "integrator": scene.integrator.name(),
        "estimator": scene.integrator.estimator_name(),
        "width": film.width,
        "height": film.height,
        "spp": film.min_spp(),
        "spp_requested": if spp == u32::MAX { Value::Null } else { spp.into() },
        "seed": seed,
        "threads": renderer.threads(),
        "device": renderer.describe(),
        "gpu_ms": rendered.gpu_ms,
        "gpu_submits": rendered.gpu_submits,
        "render_seconds": rendered.seconds,
        "interrupted": rendered.interrupted,
        "mean": film.image_mean(),
        "lookups_per_pixel": lookups_per_sample(rendered),
        "nan_samples": film.nan_samples,
        "inf_samples": film.inf_samples,
        "nonfinite_output_pixels": bad_pixels,
        "peak_memory_bytes": peak_memory_bytes(),
        "pin_grids": pin_grids(scene),
        "media": scene.media.iter().map(|m| json!({
            "source": m.source,
            "dims": m.medium.dims(),
            "precision": m.medium.data.precision_name(),
            "memory_bytes": m.medium.memory_bytes(),
        })).collect::<Vec<_>>(),
    })
}

/// The pin grids a `volpath` render gathers, from the plan, so a GPU render
/// (which gathers its own grids) reports the same without a CPU gather.
fn pin_grids(scene: &Scene) -> Option<Value> {
    let IntegratorKind::VolPath(v) = &scene.integrator else {
        return None;
    };
    let plan = v.pins.plan(&scene.world).ok().flatten()?;
    let own: Vec<_> = plan
        .iter()
        .filter_map(|p| match p {
            GridPlan::Own { spec, .. } => Some(*spec),
            GridPlan::Shared(_) => None,
        })
        .collect();
    Some(json!({
        "memory_bytes": own.iter().map(|s| s.pin_count().unwrap_or(0) * 8).sum::<u64>(),
        "positions": own.iter().map(|s| s.positions).collect::<Vec<_>>(),
    }))
}

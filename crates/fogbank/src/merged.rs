//! What `fogbank merge` reports of the parts it added up: a merged
//! render's statistics (as `render --stats` gives them, plus the shards and
//! the missing work), and a merged `stats` run's per-pixel statistics with
//! the summary `fogbank stats` writes.

use crate::stats::peak_memory_bytes;
use fogbank_eval::frame_stats::{from_film, FrameStats};
use fogbank_partial::merge::Merged;
use fogbank_partial::partial::Partial;
use serde_json::{json, Value};

/// The statistics of a merged render; `bad_pixels` is what writing its
/// images reported.
pub fn merged_render_stats(merged: &Merged, bad_pixels: usize) -> Value {
    let h = &merged.partial.header;
    let film = &merged.partial.film;
    let samples = film.total_samples();
    json!({
        "integrator": h.integrator,
        "estimator": h.estimator,
        "width": film.width,
        "height": film.height,
        "spp": film.min_spp(),
        "spp_requested": h.identity.spp,
        "seed": h.identity.seed,
        "scene_hash": h.identity.scene_hash,
        "shards": h.runs,
        "render_seconds": h.runs.iter().map(|r| r.seconds).sum::<f64>(),
        "mean": film.image_mean(),
        "lookups_per_pixel": if samples > 0 { film.lookups as f64 / samples as f64 } else { 0.0 },
        "nan_samples": film.nan_samples,
        "inf_samples": film.inf_samples,
        "nonfinite_output_pixels": bad_pixels,
        "missing": merged.missing,
        "peak_memory_bytes": peak_memory_bytes(),
    })
}

/// The per-pixel statistics of merged `stats` parts and their summary (no
/// reference: bias against one is the unsharded run's alone).
pub fn merged_frame_stats(p: &Partial, missing: &[String]) -> (FrameStats, Value) {
    let h = &p.header;
    let covered = p.covered.clone().unwrap_or_default();
    let seconds = h.runs.iter().map(|r| r.seconds).sum::<f64>();
    let st = from_film(&p.film, h.identity.spp, covered, seconds);
    let s = st.summary();
    let json = json!({
        "integrator": h.integrator,
        "estimator": h.estimator,
        "reference": Value::Null,
        "width": st.width,
        "height": st.height,
        "runs": s.runs,
        "seed": h.identity.seed,
        "shards": h.runs,
        "covered_pixels": s.pixels,
        "mean_abs_bias": Value::Null,
        "mean_bias": Value::Null,
        "mean_bias_se": s.mean_bias_se,
        "mean_std": s.mean_std,
        "rmse": Value::Null,
        "ms_per_frame": s.ms_per_frame,
        "lookups_per_pixel": s.lookups_per_pixel,
        "nonfinite_samples": st.nonfinite,
        "stats_seconds": seconds,
        "missing": missing,
        "device": "cpu",
        "peak_memory_bytes": peak_memory_bytes(),
    });
    (st, json)
}

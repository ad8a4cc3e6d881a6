//! `fogbank stats`: per-pixel mean, single-frame std and bias of an
//! estimator over K independent 1-spp frames (streamed: memory does not
//! grow with K), as EXR, false-colour maps and `summary.json`.

use crate::common::CliResult;
use crate::run_args::RunArgs;
use clap::Args;
use fogbank::stats::peak_memory_bytes;
use fogbank_estimators::Estimator;
use fogbank_eval::frame_stats::frame_stats_piece;
use fogbank_eval::{exact_reference, frame_stats, Backend, FrameStats};
use fogbank_image::image_io::{read_image, write_exr_channels};
use fogbank_render::partial::Partial;
use fogbank_render::{load_scene_or, TRANSMITTANCE_SCENE};
use std::path::PathBuf;

#[derive(Args)]
pub struct StatsArgs {
    /// Scene file (TOML); the cumulus's transmittance view (`scenes/transmittance.toml`) when omitted.
    pub scene: Option<PathBuf>,
    /// Estimator to measure (sets `integrator.estimator`; options via --set).
    #[arg(long)]
    pub estimator: Option<String>,
    /// Independent 1-spp frames.
    #[arg(long, default_value_t = 1024)]
    pub runs: u32,
    /// Exact estimator for the reference (e.g. analytic_trilinear).
    #[arg(long, conflicts_with = "reference")]
    pub reference_estimator: Option<String>,
    /// Reference image (EXR or PNG) of the same size, rendered through pixel
    /// centres (`--set render.pixel_jitter=false`).
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "stats")]
    pub out: PathBuf,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub shard: crate::shard_args::ShardArgs,
}

pub fn run(a: StatsArgs) -> CliResult {
    if a.runs == 0 {
        return Err("--runs must be at least 1".into());
    }
    let mut overrides = a.run.set.clone();
    if let Some(e) = &a.estimator {
        overrides.push(format!("integrator.estimator={e}"));
    }
    let scene = load_scene_or(a.scene.as_deref(), TRANSMITTANCE_SCENE, &overrides)?;
    let reference = match &a.reference_estimator {
        Some(n) => {
            let e = Estimator::parse(n)
                .ok_or_else(|| format!("--reference-estimator: unknown estimator `{n}`"))?;
            if e.biased() || !matches!(e, Estimator::AnalyticTrilinear | Estimator::RegularTracking)
            {
                return Err(format!("--reference-estimator must be exact (analytic_trilinear or regular_tracking), not `{n}`").into());
            }
            Some(e)
        }
        None => None,
    };
    let pool = a.run.pool()?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    if let Some(shard) = a.shard.get()? {
        if reference.is_some() || a.reference.is_some() {
            return Err(format!("--shard {}: not with a reference; merge the parts, then compare the merged mean with `fogbank compare`", shard.label()).into());
        }
        if a.run.device == crate::render_cmd::DeviceArg::Gpu {
            return Err(format!("--shard {}: not with --device gpu (GPU frames keep running means in f32, whose parts do not add up bit for bit)", shard.label()).into());
        }
        let piece = shard.piece(a.runs);
        let (film, covered, seconds) =
            pool.install(|| frame_stats_piece(&scene, &piece, a.run.seed));
        let header = fogbank_render::partial::PartialHeader::for_shard(
            "stats",
            &scene,
            a.run.seed,
            a.runs,
            &film,
            fogbank::shard_run::run(shard, a.runs, seconds, pool.current_num_threads()),
        );
        let path = a
            .out
            .join(format!("shard_{}_of_{}.fbpart", shard.index, shard.count));
        Partial {
            header,
            film,
            covered: Some(covered),
        }
        .write(&path)?;
        eprintln!(
            "shard {} ({}): {seconds:.2} s; wrote {}",
            shard.label(),
            piece.describe(),
            path.display()
        );
        return Ok(());
    }
    eprintln!(
        "{} frames of {} at {}×{} ...",
        a.runs,
        scene.integrator.estimator_name(),
        scene.camera.width,
        scene.camera.height
    );
    let gpu = a.run.gpu()?;
    let backend = Backend::from(gpu.as_ref());
    let mut st = pool
        .install(|| frame_stats(backend, &scene, a.runs, a.run.seed))
        .map_err(|e| format!("--device {}: {e}", backend.name()))?;
    if let Some(r) = reference {
        st.reference = Some(pool.install(|| exact_reference(&scene, r)));
    }
    if let Some(path) = &a.reference {
        let img = read_image(path)?;
        if (img.width, img.height) != (st.width as usize, st.height as usize) {
            return Err(format!(
                "{}: reference is {}×{}, the scene renders {}×{}",
                path.display(),
                img.width,
                img.height,
                st.width,
                st.height
            )
            .into());
        }
        st.reference = Some(img.rgb.iter().map(|p| p.map(f64::from)).collect());
    }
    let s = st.summary();
    let json = serde_json::json!({
        "integrator": scene.integrator.name(),
        "estimator": scene.integrator.estimator_name(),
        "reference": a.reference_estimator.clone().or(a.reference.as_ref().map(|p| p.display().to_string())),
        "width": st.width,
        "height": st.height,
        "runs": s.runs,
        "seed": a.run.seed,
        "threads": pool.current_num_threads(),
        "covered_pixels": s.pixels,
        "mean_abs_bias": if st.reference.is_some() { serde_json::json!(s.mean_abs_bias) } else { serde_json::Value::Null },
        "mean_bias": if st.reference.is_some() { serde_json::json!(s.mean_bias) } else { serde_json::Value::Null },
        "mean_bias_se": s.mean_bias_se,
        "mean_std": s.mean_std,
        "rmse": if st.reference.is_some() { serde_json::json!(s.rmse) } else { serde_json::Value::Null },
        "ms_per_frame": s.ms_per_frame,
        "lookups_per_pixel": s.lookups_per_pixel,
        "nonfinite_samples": st.nonfinite,
        "stats_seconds": st.seconds,
        "device": backend.name(),
        "peak_memory_bytes": peak_memory_bytes(),
    });
    write_outputs(&st, scene.integrator.estimator_name(), &a.out, &json)
}

/// Writes `stats.exr` (mean, std, bias when known, count), the false-colour
/// maps and `summary.json` into `out`, and prints the summary.
pub fn write_outputs(
    st: &FrameStats,
    estimator: &str,
    out: &std::path::Path,
    json: &serde_json::Value,
) -> CliResult {
    let to32 = |v: &[[f64; 3]], f: &dyn Fn(f64) -> f64| -> Vec<[f32; 3]> {
        v.iter().map(|p| p.map(|c| f(c) as f32)).collect()
    };
    let mut layers: Vec<(&str, Vec<[f32; 3]>)> = vec![
        ("mean", to32(&st.mean, &|c| c)),
        ("std", to32(&st.variance, &|c| c.sqrt())),
    ];
    if let Some(b) = st.bias() {
        layers.push(("bias", to32(&b, &|c| c)));
    }
    let counts: Vec<f32> = st.count.iter().map(|&c| c as f32).collect();
    write_exr_channels(
        &out.join("stats.exr"),
        st.width,
        st.height,
        &layers,
        Some(("count", &counts)),
    )?;
    fogbank_eval::maps::write_maps(st, estimator, &out.join("maps"))?;
    std::fs::write(
        out.join("summary.json"),
        serde_json::to_string_pretty(json)? + "\n",
    )?;
    println!("{}", serde_json::to_string_pretty(json)?);
    Ok(())
}

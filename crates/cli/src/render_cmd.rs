//! `fogbank render`: progressive rendering with a progress bar, Ctrl-C that
//! keeps what was accumulated, EXR/PNG output and a JSON statistics file.

use crate::common::{peak_memory_bytes, thread_pool, CliResult};
use clap::Args;
use fogbank_render::integrators::shared::pin_params::GridPlan;
use fogbank_render::partial::Partial;
use fogbank_render::shard::{Piece, Shard};
use fogbank_render::{load_scene, render_piece, Progress, RenderOptions};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML). Without it, the built-in default scene.
    pub scene: Option<PathBuf>,
    /// Output image: `.exr` (linear float) or `.png` (sRGB). Default: fogbank.exr and fogbank.png.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Samples per pixel (overrides `render.spp`).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Stop after this many seconds (with --spp: whichever comes first).
    #[arg(long)]
    pub time_budget: Option<f64>,
    /// Scene seed (overrides `render.seed`).
    #[arg(long)]
    pub seed: Option<u32>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Write render statistics as JSON.
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// Override a scene key: `--set integrator.estimator=track_length`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// PNG exposure in stops (overrides `render.exposure`).
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// PNG tone curve: linear, aces or agx (overrides `render.tonemap`).
    #[arg(long)]
    pub tonemap: Option<String>,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Where to render: `cpu` (the reference) or `gpu` (wgpu compute; fails
    /// with a clear message when no adapter exists).
    #[arg(long, value_enum, default_value_t = Device::Cpu)]
    pub device: Device,
    /// Render frames of the scene's `[animation]`: `A..B` (end excluded),
    /// `A..=B` or `N`; one file per frame (`-o out_{frame:04}.exr`, or
    /// `_0042` inserted before the extension). `restir` carries its
    /// reservoirs from frame to frame.
    #[arg(long, value_name = "A..B")]
    pub frames: Option<String>,
    #[command(flatten)]
    pub shard: crate::shard_args::ShardArgs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    Cpu,
    Gpu,
}

pub fn run(a: RenderArgs) -> CliResult {
    let mut overrides = a.set.clone();
    if let Some(s) = a.spp {
        overrides.push(format!("render.spp={s}"));
    }
    if let Some(s) = a.seed {
        overrides.push(format!("render.seed={s}"));
    }
    if let Some(e) = a.exposure {
        overrides.push(format!("render.exposure={e:?}"));
    }
    if let Some(t) = &a.tonemap {
        fogbank_image::ToneCurve::parse(t).map_err(|e| format!("--tonemap: {e}"))?;
        overrides.push(format!("render.tonemap={t}"));
    }
    let shard = a.shard.get()?;
    let outputs: Vec<PathBuf> = match &a.output {
        None if shard.is_some() => {
            let s = shard.unwrap();
            let frame = if a.frames.is_some() {
                "_{frame:04}"
            } else {
                ""
            };
            vec![PathBuf::from(format!(
                "fogbank{frame}_shard_{}_of_{}.fbpart",
                s.index, s.count
            ))]
        }
        None if a.frames.is_some() => vec![PathBuf::from("fogbank_{frame:04}.exr")],
        Some(p) => {
            match (p.extension().and_then(|e| e.to_str()), shard.is_some()) {
                (Some("exr") | Some("png"), false) | (Some("fbpart"), true) => {}
                (_, false) => return Err(format!("{}: output must end in .exr or .png", p.display()).into()),
                (_, true) => return Err(format!("{}: a shard's output is a partial result and must end in .fbpart (merge the parts with `fogbank merge`)", p.display()).into()),
            }
            vec![p.clone()]
        }
        None => vec![PathBuf::from("fogbank.exr"), PathBuf::from("fogbank.png")],
    };
    if let Some(s) = shard {
        check_shardable(&a, s)?;
    }
    if let Some(b) = a.time_budget {
        if !(b > 0.0 && b.is_finite()) {
            return Err("--time-budget must be a positive number of seconds".into());
        }
    }
    let scene = load_scene(a.scene.as_deref(), &overrides)?;
    if let Some(note) = scene.integrator.notice(&scene.world).filter(|_| !a.quiet) {
        eprintln!("note: {note}");
    }
    let spp = match (a.spp, a.time_budget) {
        (None, Some(_)) => u32::MAX,
        _ => scene.desc.render.spp,
    };
    if spp == 0 {
        return Err("render.spp must be at least 1".into());
    }
    let opts = RenderOptions {
        spp,
        seed: scene.desc.render.seed,
        time_budget: a.time_budget.map(Duration::from_secs_f64),
    };
    if shard.is_some()
        && matches!(
            scene.integrator,
            fogbank_render::integrators::IntegratorKind::Restir(_)
        )
    {
        return Err("--shard: `restir` carries reservoirs from pass to pass and pixel to pixel, so its parts cannot be rendered apart; render it whole".into());
    }
    let pool = thread_pool(a.threads)?;
    let threads = pool.current_num_threads();
    if let Some(frames) = &a.frames {
        let gpu = match a.device {
            Device::Cpu => None,
            Device::Gpu => Some(fogbank_gpu::Gpu::new().map_err(|e| format!("--device gpu: {e}"))?),
        };
        if a.time_budget.is_some() {
            return Err("--frames takes --spp, not --time-budget".into());
        }
        let progress = Arc::new(Progress::default());
        let p = progress.clone();
        let _ = ctrlc::set_handler(move || {
            if p.cancel.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
        return crate::frames_cmd::run(
            crate::frames_cmd::FramesArgs {
                frames,
                outputs,
                spp,
                seed: opts.seed,
                tone: scene.desc.render.tone_mapping(),
                quiet: a.quiet,
                gpu: gpu.as_ref(),
                shard,
            },
            scene,
            &pool,
            &progress,
        );
    }
    let gpu = match a.device {
        Device::Cpu => None,
        Device::Gpu => Some(fogbank_gpu::Gpu::new().map_err(|e| format!("--device gpu: {e}"))?),
    };

    let progress = Arc::new(Progress::default());
    {
        let p = progress.clone();
        // A second Ctrl-C while writing falls through to the default handler.
        let _ = ctrlc::set_handler(move || {
            if p.cancel.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
    }
    let piece = shard.map_or(Piece::whole(spp), |s| s.piece(spp));
    let (w, h) = (scene.camera.width, scene.camera.height);
    let pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| piece.has_pixel(x, y, w))
        .count() as u64;
    let work = pixels * (piece.samples[1] - piece.samples[0]) as u64;
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else if spp == u32::MAX {
        let b = ProgressBar::new((a.time_budget.unwrap_or(0.0) * 1000.0) as u64);
        b.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {msg}").unwrap(),
        );
        b
    } else {
        let b = ProgressBar::new(work);
        b.set_style(
            ProgressStyle::with_template(
                "[{elapsed_precise}] {wide_bar} {percent:>3}% ETA {eta} {msg}",
            )
            .unwrap()
            .progress_chars("█▉▊▋▌▍▎▏ "),
        );
        b
    };
    let done = std::sync::atomic::AtomicBool::new(false);
    let result = std::thread::scope(|s| {
        s.spawn(|| {
            let start = std::time::Instant::now();
            while !done.load(Ordering::Relaxed) {
                let samples = progress.samples_done.load(Ordering::Relaxed);
                if spp == u32::MAX {
                    bar.set_position(start.elapsed().as_millis() as u64);
                } else {
                    bar.set_position(samples);
                }
                bar.set_message(format!(
                    "{} spp",
                    progress.passes_done.load(Ordering::Relaxed)
                ));
                std::thread::sleep(Duration::from_millis(100));
            }
        });
        let r = match &gpu {
            None => Ok((
                pool.install(|| render_piece(&scene, &opts, &piece, &progress)),
                None,
            )),
            Some(g) => fogbank_gpu::render::render(g, &scene, &opts, &progress).map(|r| {
                let gpu = (r.gpu_ms, r.submits);
                (
                    fogbank_render::RenderResult {
                        film: r.film,
                        seconds: r.seconds,
                        interrupted: r.interrupted,
                    },
                    Some(gpu),
                )
            }),
        };
        done.store(true, Ordering::Relaxed);
        r
    });
    let (result, gpu_run) = result.map_err(|e| format!("--device gpu: {e}"))?;
    bar.finish_and_clear();

    let film = &result.film;
    if let Some(s) = shard {
        if result.interrupted {
            return Err(format!(
                "interrupted: shard {} wrote no partial result (a part must be complete to merge)",
                s.label()
            )
            .into());
        }
        let header = fogbank_render::partial::PartialHeader::for_shard(
            "render",
            &scene,
            opts.seed,
            spp,
            film,
            crate::shard_args::run(s, spp, result.seconds, threads),
        );
        let partial = Partial {
            header,
            film: result.film.clone(),
            covered: None,
        };
        partial.write(&outputs[0])?;
        if !a.quiet {
            eprintln!(
                "shard {} ({}): {:.2} s, {} threads; wrote {}",
                s.label(),
                piece.describe(),
                result.seconds,
                threads,
                outputs[0].display()
            );
        }
        return Ok(());
    }
    let bad_pixels =
        crate::film_out::write_images(&outputs, film, &scene.desc.render.tone_mapping())?;
    let min_spp = film.min_spp();
    let samples = film.total_samples();
    let lookups_per_pixel = if samples > 0 {
        film.lookups as f64 / samples as f64
    } else {
        0.0
    };
    if !a.quiet {
        eprintln!(
            "{}{} spp ({}), {:.2} s, {} threads, {:.1} lookups/pixel/sample{}; wrote {}",
            if result.interrupted {
                "interrupted after "
            } else {
                ""
            },
            min_spp,
            scene.integrator.estimator_name(),
            result.seconds,
            threads,
            lookups_per_pixel,
            if film.nan_samples + film.inf_samples > 0 {
                format!(
                    ", dropped {} NaN and {} Inf samples",
                    film.nan_samples, film.inf_samples
                )
            } else {
                String::new()
            },
            outputs
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if let Some(path) = &a.stats {
        let m = film.image_mean();
        let json = serde_json::json!({
            "integrator": scene.integrator.name(),
            "estimator": scene.integrator.estimator_name(),
            "width": film.width,
            "height": film.height,
            "spp": min_spp,
            "spp_requested": if spp == u32::MAX { serde_json::Value::Null } else { spp.into() },
            "seed": opts.seed,
            "threads": threads,
            "device": gpu.as_ref().map_or("cpu".to_string(), |g| format!("gpu: {}", g.describe())),
            "gpu_ms": gpu_run.and_then(|g| g.0),
            "gpu_submits": gpu_run.map(|g| g.1),
            "render_seconds": result.seconds,
            "interrupted": result.interrupted,
            "mean": m,
            "lookups_per_pixel": lookups_per_pixel,
            "nan_samples": film.nan_samples,
            "inf_samples": film.inf_samples,
            "nonfinite_output_pixels": bad_pixels,
            "peak_memory_bytes": peak_memory_bytes(),
            "pin_grids": match &scene.integrator {
                // From the plan, so a GPU render (which gathers its own
                // grids) reports the same without a CPU gather.
                fogbank_render::integrators::IntegratorKind::VolPath(v) => v.pins.plan(&scene.world).ok().flatten().map(|plan| {
                    let own: Vec<_> = plan.iter().filter_map(|p| match p {
                        GridPlan::Own { spec, .. } => Some(*spec),
                        GridPlan::Shared(_) => None,
                    }).collect();
                    serde_json::json!({
                        "memory_bytes": own.iter().map(|s| s.pin_count().unwrap_or(0) * 8).sum::<u64>(),
                        "positions": own.iter().map(|s| s.positions).collect::<Vec<_>>(),
                    })
                }),
                _ => None,
            },
            "media": scene.media.iter().map(|m| serde_json::json!({
                "source": m.source,
                "dims": m.medium.dims(),
                "precision": m.medium.data.precision_name(),
                "memory_bytes": m.medium.memory_bytes(),
            })).collect::<Vec<_>>(),
        });
        crate::common::write_json(path, &json)?;
    }
    Ok(())
}

/// What a shard cannot be combined with.
fn check_shardable(a: &RenderArgs, s: Shard) -> CliResult {
    let why = if a.time_budget.is_some() {
        "--time-budget: a shard's part of the work is fixed by spp; give --spp"
    } else if a.device == Device::Gpu {
        "--device gpu: GPU films keep running means in f32, whose parts do not add up bit for bit; shard CPU renders"
    } else if a.stats.is_some() {
        "--stats: a shard writes its statistics into the partial; `fogbank merge --stats` writes them for the whole"
    } else {
        return Ok(());
    };
    Err(format!("--shard {}: not with {why}", s.label()).into())
}

//! `fogbank render`: the command-line face of the library's render job
//! (`fogbank::RenderJob`): arguments to scene overrides and a job, a
//! progress bar on stderr, Ctrl-C that keeps what was accumulated, and the
//! EXR/PNG, partial and JSON files the library writes.

use crate::common::CliResult;
use clap::Args;
use fogbank::output::{write_images, write_partial};
use fogbank::stats::{lookups_per_sample, render_stats};
use fogbank::{load_scene, Device, Progress, RenderJob, Rendered, Renderer, Scene, Shard};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file: fogbank TOML (`.toml`), Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`). Without it, the built-in default scene.
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
    #[arg(long, value_enum, default_value_t = DeviceArg::Cpu)]
    pub device: DeviceArg,
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
pub enum DeviceArg {
    Cpu,
    Gpu,
}

impl DeviceArg {
    pub(crate) fn device(self) -> Device {
        match self {
            DeviceArg::Cpu => Device::Cpu,
            DeviceArg::Gpu => Device::Gpu,
        }
    }
}

/// The scene overrides the flags stand for (`--spp`, `--seed`, …).
fn overrides(a: &RenderArgs) -> Result<Vec<String>, String> {
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
        fogbank::image::ToneCurve::parse(t).map_err(|e| format!("--tonemap: {e}"))?;
        overrides.push(format!("render.tonemap={t}"));
    }
    Ok(overrides)
}

/// The files to write: `-o`, or the defaults for a shard, a frame sequence
/// or a plain render.
fn outputs(a: &RenderArgs, shard: Option<Shard>) -> Result<Vec<PathBuf>, String> {
    let frame = if a.frames.is_some() {
        "_{frame:04}"
    } else {
        ""
    };
    Ok(match (&a.output, shard) {
        (None, Some(s)) => vec![PathBuf::from(format!(
            "fogbank{frame}_shard_{}_of_{}.fbpart",
            s.index, s.count
        ))],
        (None, None) if a.frames.is_some() => vec![PathBuf::from("fogbank_{frame:04}.exr")],
        (None, None) => vec![PathBuf::from("fogbank.exr"), PathBuf::from("fogbank.png")],
        (Some(p), _) => {
            match (p.extension().and_then(|e| e.to_str()), shard.is_some()) {
                (Some("exr") | Some("png"), false) | (Some("fbpart"), true) => {}
                (_, false) => return Err(format!("{}: output must end in .exr or .png", p.display())),
                (_, true) => return Err(format!("{}: a shard's output is a partial result and must end in .fbpart (merge the parts with `fogbank merge`)", p.display())),
            }
            vec![p.clone()]
        }
    })
}

pub fn run(a: RenderArgs) -> CliResult {
    let overrides = overrides(&a)?;
    let shard = a.shard.get()?;
    let outputs = outputs(&a, shard)?;
    let job = RenderJob {
        spp: a.spp,
        time_budget: a.time_budget,
        shard,
    };
    if let (Some(s), Some(_)) = (shard, &a.stats) {
        return Err(format!("--shard {}: not with --stats: a shard writes its statistics into the partial; `fogbank merge --stats` writes them for the whole", s.label()).into());
    }
    job.check_shard(a.device.device())?;
    if let Some(b) = a.time_budget {
        if !(b > 0.0 && b.is_finite()) {
            return Err("--time-budget must be a positive number of seconds".into());
        }
    }
    let scene = load_scene(a.scene.as_deref(), &overrides)?;
    if let Some(note) = scene.integrator.notice(&scene.world).filter(|_| !a.quiet) {
        eprintln!("note: {note}");
    }
    job.check_integrator(&scene)?;
    let spp = job.spp(&scene);
    if a.threads == Some(0) {
        return Err("--threads must be at least 1".into());
    }
    let renderer = Renderer::new(a.device.device(), a.threads)?;
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
    if let Some(frames) = &a.frames {
        return crate::frames_cmd::run(
            frames, &scene, &renderer, job, &outputs, a.quiet, &progress,
        );
    }
    let work = job
        .piece(spp)
        .pixel_samples(scene.camera.width, scene.camera.height);
    let bar = progress_bar(a.quiet, spp, a.time_budget, work);
    let rendered = while_showing(&bar, &progress, spp == u32::MAX, || {
        job.run(&renderer, &scene, &progress, None)
    })?;
    bar.finish_and_clear();
    if let Some(s) = shard {
        return write_shard(&outputs[0], &scene, &renderer, spp, s, rendered, a.quiet);
    }
    let bad_pixels = write_images(&outputs, &rendered.film, &scene.desc.render.tone_mapping())?;
    if !a.quiet {
        eprintln!("{}", summary(&scene, &renderer, &rendered, &outputs));
    }
    if let Some(path) = &a.stats {
        let seed = scene.desc.render.seed;
        let json = render_stats(&scene, &renderer, &rendered, spp, seed, bad_pixels);
        crate::common::write_json(path, &json)?;
    }
    Ok(())
}

/// The bar: samples done with an ETA, or elapsed time against a budget.
fn progress_bar(quiet: bool, spp: u32, budget: Option<f64>, work: u64) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    if spp == u32::MAX {
        let b = ProgressBar::new((budget.unwrap_or(0.0) * 1000.0) as u64);
        b.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {msg}").unwrap(),
        );
        return b;
    }
    let b = ProgressBar::new(work);
    b.set_style(
        ProgressStyle::with_template(
            "[{elapsed_precise}] {wide_bar} {percent:>3}% ETA {eta} {msg}",
        )
        .unwrap()
        .progress_chars("█▉▊▋▌▍▎▏ "),
    );
    b
}

/// Runs `f` while a thread moves `bar` with `progress` (by time when
/// `by_time`, else by samples) ten times a second.
fn while_showing<T: Send>(
    bar: &ProgressBar,
    progress: &Progress,
    by_time: bool,
    f: impl FnOnce() -> T + Send,
) -> T {
    let done = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|s| {
        s.spawn(|| {
            let start = std::time::Instant::now();
            while !done.load(Ordering::Relaxed) {
                if by_time {
                    bar.set_position(start.elapsed().as_millis() as u64);
                } else {
                    bar.set_position(progress.samples_done.load(Ordering::Relaxed));
                }
                bar.set_message(format!(
                    "{} spp",
                    progress.passes_done.load(Ordering::Relaxed)
                ));
                std::thread::sleep(Duration::from_millis(100));
            }
        });
        let r = f();
        done.store(true, Ordering::Relaxed);
        r
    })
}

/// A shard's partial result, written only when the part is complete.
fn write_shard(
    out: &std::path::Path,
    scene: &Scene,
    renderer: &Renderer,
    spp: u32,
    s: Shard,
    rendered: Rendered,
    quiet: bool,
) -> CliResult {
    if rendered.interrupted {
        return Err(format!(
            "interrupted: shard {} wrote no partial result (a part must be complete to merge)",
            s.label()
        )
        .into());
    }
    let seconds = rendered.seconds;
    write_partial(out, scene, spp, s, rendered, renderer.threads(), None)?;
    if !quiet {
        eprintln!(
            "shard {} ({}): {:.2} s, {} threads; wrote {}",
            s.label(),
            s.piece(spp).describe(),
            seconds,
            renderer.threads(),
            out.display()
        );
    }
    Ok(())
}

/// The line printed after a render.
fn summary(scene: &Scene, renderer: &Renderer, rendered: &Rendered, outputs: &[PathBuf]) -> String {
    let film = &rendered.film;
    let dropped = if film.nan_samples + film.inf_samples > 0 {
        format!(
            ", dropped {} NaN and {} Inf samples",
            film.nan_samples, film.inf_samples
        )
    } else {
        String::new()
    };
    let written: Vec<String> = outputs.iter().map(|p| p.display().to_string()).collect();
    format!(
        "{}{} spp ({}), {:.2} s, {} threads, {:.1} lookups/pixel/sample{dropped}; wrote {}",
        if rendered.interrupted {
            "interrupted after "
        } else {
            ""
        },
        film.min_spp(),
        scene.integrator.estimator_name(),
        rendered.seconds,
        renderer.threads(),
        lookups_per_sample(rendered),
        written.join(", ")
    )
}

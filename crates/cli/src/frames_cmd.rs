//! `fogbank render SCENE --frames A..B`: a frame sequence of an animated
//! scene (`[animation]`), one output file per frame, one progress bar and a
//! statistics line per frame. `restir` carries its reservoirs from frame to
//! frame (temporal reuse sees the previous frame's camera, volume and
//! lights); the other integrators render every frame with `spp` samples.
//! A frame that fails to build (a missing per-frame file) stops the
//! sequence; the frames already written stay intact.

use crate::common::CliResult;
use crate::film_out::film_rgb;
use fogbank_image::image_io::{write_exr, write_png};
use fogbank_render::integrators::restir::frame::Sequence;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::partial::Partial;
use fogbank_render::shard::Shard;
use fogbank_render::{render, render_piece, Progress, RenderOptions, Scene};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Frames `A..B` (end excluded), `A..=B` or a single `N`.
pub fn parse_frames(s: &str, frames: u32) -> Result<std::ops::Range<u32>, String> {
    let bad = || format!("--frames {s}: expected A..B, A..=B or N");
    let num = |t: &str| t.trim().parse::<u32>().map_err(|_| bad());
    let range = if let Some((a, b)) = s.split_once("..=") {
        num(a)?..num(b)?.saturating_add(1)
    } else if let Some((a, b)) = s.split_once("..") {
        num(a)?..num(b)?
    } else {
        let n = num(s)?;
        n..n.saturating_add(1)
    };
    if range.is_empty() || range.end > frames {
        return Err(format!(
            "--frames {s}: the animation has frames 0..={} (and the range must not be empty)",
            frames - 1
        ));
    }
    Ok(range)
}

/// The output file of `frame`: `{frame}` / `{frame:04}` in `pattern`
/// replaced, or `_0042` inserted before the extension.
pub fn frame_output(pattern: &Path, frame: u32) -> PathBuf {
    let s = pattern.display().to_string();
    if s.contains("{frame") {
        return PathBuf::from(fogbank_render::animation::frame_path(&s, frame));
    }
    let stem = pattern
        .file_stem()
        .and_then(|x| x.to_str())
        .unwrap_or("fogbank");
    let ext = pattern
        .extension()
        .and_then(|x| x.to_str())
        .unwrap_or("exr");
    pattern.with_file_name(format!("{stem}_{frame:04}.{ext}"))
}

pub struct FramesArgs<'a> {
    pub frames: &'a str,
    pub outputs: Vec<PathBuf>,
    pub spp: u32,
    pub seed: u32,
    pub tone: fogbank_image::ToneMapping,
    pub quiet: bool,
    /// `--device gpu`: the device every frame renders on.
    pub gpu: Option<&'a fogbank_gpu::Gpu>,
    /// `--shard I/N`: each frame's part, written as a partial result per
    /// frame (`fogbank merge` adds up one frame's parts).
    pub shard: Option<Shard>,
}

pub fn run(
    a: FramesArgs,
    first: Scene,
    pool: &rayon::ThreadPool,
    progress: &Progress,
) -> CliResult {
    let Some(anim) = &first.desc.animation else {
        return Err(
            "--frames: the scene has no [animation] table (see `fogbank render --help`)".into(),
        );
    };
    let range = parse_frames(a.frames, anim.frames)?;
    let first = first.at_frame(range.start)?;
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(range.len() as u64);
        b.set_style(
            ProgressStyle::with_template(
                "[{elapsed_precise}] {wide_bar} frame {pos}/{len} ETA {eta}",
            )
            .unwrap(),
        );
        b
    };
    let restir = match &first.integrator {
        IntegratorKind::Restir(r) => Some(r),
        _ => None,
    };
    let mut sequence = restir
        .filter(|_| a.gpu.is_none())
        .map(|r| Sequence::new(r, a.seed, 0));
    let mut sequence_gpu = match (a.gpu, restir) {
        (Some(g), Some(_)) => Some(
            fogbank_gpu::restir::SequenceGpu::new(g, &first, a.seed)
                .map_err(|e| format!("--device gpu: {e}"))?,
        ),
        _ => None,
    };
    let mut prev: Option<Scene> = None;
    for f in range.clone() {
        if progress.cancel.load(Ordering::Relaxed) {
            bar.abandon();
            eprintln!("interrupted before frame {f}; earlier frames are written");
            return Ok(());
        }
        let scene = if f == range.start {
            first.clone()
        } else {
            first.at_frame(f)?
        };
        let clock = Instant::now();
        let (rgb, variance) = match (&mut sequence, &scene.integrator) {
            _ if a.gpu.is_some() => {
                let gpu = a.gpu.expect("checked");
                let film = match &mut sequence_gpu {
                    Some(seq) => seq.frame(gpu, &scene),
                    None => {
                        let opts = RenderOptions {
                            spp: a.spp,
                            seed: a.seed,
                            time_budget: None,
                        };
                        fogbank_gpu::render::render(gpu, &scene, &opts, progress).map(|r| r.film)
                    }
                }
                .map_err(|e| format!("frame {f}: --device gpu: {e}"))?;
                let img = film_rgb(&film);
                (img.rgb, img.variance)
            }
            (Some(seq), IntegratorKind::Restir(r)) => {
                let before = prev.as_ref().unwrap_or(&scene);
                let prev_restir = match &before.integrator {
                    IntegratorKind::Restir(p) => p,
                    _ => r,
                };
                let (cur, old) = (r.data(&scene.world), prev_restir.data(&before.world));
                let out = pool.install(|| seq.frame(&cur, &old));
                let rgb: Vec<[f32; 3]> = out
                    .radiance
                    .iter()
                    .map(|l| l.to_array().map(|c| if c.is_finite() { c } else { 0.0 }))
                    .collect();
                (rgb, None)
            }
            _ => {
                let opts = RenderOptions {
                    spp: a.spp,
                    seed: a.seed,
                    time_budget: None,
                };
                if let Some(s) = a.shard {
                    let r = pool.install(|| render_piece(&scene, &opts, &s.piece(a.spp), progress));
                    if r.interrupted {
                        bar.abandon();
                        return Err(format!("interrupted in frame {f}: its shard {} wrote no partial result; earlier frames are written", s.label()).into());
                    }
                    let run =
                        crate::shard_args::run(s, a.spp, r.seconds, pool.current_num_threads());
                    let mut header = fogbank_render::partial::PartialHeader::for_shard(
                        "render", &scene, a.seed, a.spp, &r.film, run,
                    );
                    header.identity.frame = Some(f);
                    let out = frame_output(&a.outputs[0], f);
                    Partial {
                        header,
                        film: r.film,
                        covered: None,
                    }
                    .write(&out)?;
                    bar.suspend(|| {
                        if !a.quiet {
                            eprintln!(
                                "frame {f}: shard {} in {:.3} s, wrote {}",
                                s.label(),
                                r.seconds,
                                out.display()
                            );
                        }
                    });
                    bar.inc(1);
                    continue;
                }
                let img = film_rgb(&pool.install(|| render(&scene, &opts, progress)).film);
                (img.rgb, img.variance)
            }
        };
        let seconds = clock.elapsed().as_secs_f64();
        let (w, h) = (scene.camera.width, scene.camera.height);
        let mut written = Vec::new();
        for pattern in &a.outputs {
            let out = frame_output(pattern, f);
            match out.extension().and_then(|e| e.to_str()) {
                Some("png") => write_png(&out, w, h, &rgb, &a.tone)?,
                _ => write_exr(&out, w, h, &rgb, variance.as_deref())?,
            }
            written.push(out.display().to_string());
        }
        let mean: [f64; 3] = std::array::from_fn(|c| {
            rgb.iter().map(|p| p[c] as f64).sum::<f64>() / rgb.len().max(1) as f64
        });
        bar.suspend(|| {
            if !a.quiet {
                eprintln!(
                    "frame {f}: {:.3} s, mean [{:.4}, {:.4}, {:.4}], wrote {}",
                    seconds,
                    mean[0],
                    mean[1],
                    mean[2],
                    written.join(", ")
                );
            }
        });
        bar.inc(1);
        prev = Some(scene);
    }
    bar.finish_and_clear();
    Ok(())
}

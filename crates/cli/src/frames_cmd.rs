//! `fogbank render SCENE --frames A..B`: the library's frame sequence
//! (`fogbank::frames`) with one output file per frame (or a partial per
//! frame for a shard), one progress bar and a statistics line per frame.
//! A frame that fails to build stops the sequence; the frames already
//! written stay intact.

use crate::common::CliResult;
use fogbank::frames::{frame_output, parse_frames, Frame, FrameSequence};
use fogbank::output::{write_image, write_partial};
use fogbank::{ErrorKind, Progress, RenderJob, Renderer, Scene};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;

pub fn run(
    frames: &str,
    scene: &Scene,
    renderer: &Renderer,
    job: RenderJob,
    outputs: &[PathBuf],
    quiet: bool,
    progress: &Progress,
) -> CliResult {
    let Some(anim) = &scene.desc.animation else {
        return Err(
            "--frames: the scene has no [animation] table (see `fogbank render --help`)".into(),
        );
    };
    let range = parse_frames(frames, anim.frames)?;
    let first = scene.at_frame(range.start)?;
    let bar = if quiet {
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
    let spp = job.spp(&first);
    let shard = job.shard;
    for frame in FrameSequence::new(&first, range, renderer, job, progress)? {
        let frame = match frame {
            Err(e) if e.kind == ErrorKind::Interrupted => {
                bar.abandon();
                eprintln!("{}", e.message.replace("are done", "are written"));
                return Ok(());
            }
            other => other?,
        };
        let line = write_frame(frame, outputs, renderer, spp, shard, &bar)?;
        bar.suspend(|| {
            if !quiet {
                eprintln!("{line}");
            }
        });
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(())
}

/// Writes a frame's files; returns its statistics line.
fn write_frame(
    frame: Frame,
    outputs: &[PathBuf],
    renderer: &Renderer,
    spp: u32,
    shard: Option<fogbank::Shard>,
    bar: &ProgressBar,
) -> Result<String, Box<dyn std::error::Error>> {
    let f = frame.index;
    if let (Some(s), Some(part)) = (shard, frame.part) {
        if part.interrupted {
            bar.abandon();
            return Err(format!("interrupted in frame {f}: its shard {} wrote no partial result; earlier frames are written", s.label()).into());
        }
        let seconds = part.seconds;
        let out = frame_output(&outputs[0], f);
        write_partial(
            &out,
            &frame.scene,
            spp,
            s,
            part,
            renderer.threads(),
            Some(f),
        )?;
        return Ok(format!(
            "frame {f}: shard {} in {seconds:.3} s, wrote {}",
            s.label(),
            out.display()
        ));
    }
    let img = frame.image.expect("a whole frame has an image");
    let (w, h) = (frame.scene.camera.width, frame.scene.camera.height);
    let tone = frame.scene.desc.render.tone_mapping();
    let mut written = Vec::new();
    for pattern in outputs {
        let out = frame_output(pattern, f);
        write_image(&out, w, h, &img.rgb, img.variance.as_deref(), &tone)?;
        written.push(out.display().to_string());
    }
    let mean: [f64; 3] = std::array::from_fn(|c| {
        img.rgb.iter().map(|p| p[c] as f64).sum::<f64>() / img.rgb.len().max(1) as f64
    });
    Ok(format!(
        "frame {f}: {:.3} s, mean [{:.4}, {:.4}, {:.4}], wrote {}",
        frame.seconds,
        mean[0],
        mean[1],
        mean[2],
        written.join(", ")
    ))
}

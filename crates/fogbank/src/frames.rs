//! Frame sequences of an animated scene (`[animation]`): each frame built
//! from the first and rendered in turn. `restir` carries its reservoirs
//! from frame to frame (temporal reuse sees the previous frame's camera,
//! volume and lights); the other integrators render every frame with the
//! job's samples, whole or as a shard's part. A frame that fails to build
//! (a missing per-frame file) ends the sequence with its error.

use crate::error::{Error, ErrorKind};
use crate::job::RenderJob;
use crate::output::{film_rgb, FilmImage};
use crate::renderer::{Rendered, Renderer};
use fogbank_render::integrators::restir::frame::Sequence;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{Progress, Scene};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Frames `A..B` (end excluded), `A..=B` or a single `N` of an animation of
/// `frames` frames.
pub fn parse_frames(s: &str, frames: u32) -> Result<Range<u32>, Error> {
    let bad = || Error::invalid(format!("--frames {s}: expected A..B, A..=B or N"));
    let num = |t: &str| t.trim().parse::<u32>().map_err(|_| bad());
    let range = if let Some((a, b)) = s.split_once("..=") {
        num(a)?..num(b)?.saturating_add(1)
    } else if let Some((a, b)) = s.split_once("..") {
        num(a)?..num(b)?
    } else {
        let n = num(s)?;
        n..n.saturating_add(1)
    };
    check_frames(&range, frames).map_err(|_| {
        Error::invalid(format!(
            "--frames {s}: the animation has frames 0..={} (and the range must not be empty)",
            frames.saturating_sub(1)
        ))
    })?;
    Ok(range)
}

fn check_frames(range: &Range<u32>, frames: u32) -> Result<(), Error> {
    if range.is_empty() || range.end > frames {
        return Err(Error::invalid(format!(
            "frames {}..{}: the animation has frames 0..={}",
            range.start,
            range.end,
            frames.saturating_sub(1)
        )));
    }
    Ok(())
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

/// One rendered frame.
pub struct Frame {
    pub index: u32,
    pub scene: Scene,
    /// Seconds for the frame (building excluded, reuse passes included).
    pub seconds: f64,
    /// The image (whole renders).
    pub image: Option<FilmImage>,
    /// A shard's part (`job.shard`), for a partial result.
    pub part: Option<Rendered>,
}

/// The frames of `range` of the animated scene `first`, rendered on
/// `renderer` as `job` says (its `spp`, or the scene's; its shard).
pub struct FrameSequence<'a> {
    first: &'a Scene,
    frames: Range<u32>,
    renderer: &'a Renderer,
    job: RenderJob,
    progress: &'a Progress,
    restir_cpu: Option<Sequence<'a>>,
    restir_gpu: Option<fogbank_gpu::restir::SequenceGpu>,
    prev: Option<Scene>,
}

impl<'a> FrameSequence<'a> {
    /// `first` is the scene at frame `frames.start` (see `Scene::at_frame`).
    pub fn new(
        first: &'a Scene,
        frames: Range<u32>,
        renderer: &'a Renderer,
        job: RenderJob,
        progress: &'a Progress,
    ) -> Result<FrameSequence<'a>, Error> {
        let Some(anim) = &first.desc.animation else {
            return Err(Error::invalid(
                "--frames: the scene has no [animation] table (see `fogbank render --help`)",
            ));
        };
        check_frames(&frames, anim.frames)?;
        if job.time_budget.is_some() {
            return Err(Error::invalid("--frames takes --spp, not --time-budget"));
        }
        let seed = first.desc.render.seed;
        let restir = match &first.integrator {
            IntegratorKind::Restir(r) => Some(r),
            _ => None,
        };
        job.check_shard(renderer.device())?;
        job.check_integrator(first)?;
        let gpu = renderer.gpu_device();
        let restir_cpu = restir
            .filter(|_| gpu.is_none())
            .map(|r| Sequence::new(r, seed, 0));
        let restir_gpu = match (gpu, restir) {
            (Some(g), Some(_)) => Some(
                fogbank_gpu::restir::SequenceGpu::new(g, first, seed)
                    .map_err(|e| Error::runtime(format!("--device gpu: {e}")))?,
            ),
            _ => None,
        };
        Ok(FrameSequence {
            first,
            frames,
            renderer,
            job,
            progress,
            restir_cpu,
            restir_gpu,
            prev: None,
        })
    }

    fn render(&mut self, f: u32, scene: Scene) -> Result<Frame, Error> {
        let clock = Instant::now();
        let mut frame = Frame {
            index: f,
            scene,
            seconds: 0.0,
            image: None,
            part: None,
        };
        let scene = &frame.scene;
        if let Some(seq) = &mut self.restir_gpu {
            let gpu = self.renderer.gpu_device().expect("a GPU sequence");
            let film = seq
                .frame(gpu, scene)
                .map_err(|e| Error::runtime(format!("frame {f}: --device gpu: {e}")))?;
            frame.image = Some(film_rgb(&film));
        } else if let (Some(seq), IntegratorKind::Restir(r)) =
            (&mut self.restir_cpu, &scene.integrator)
        {
            let before = self.prev.as_ref().unwrap_or(scene);
            let prev_restir = match &before.integrator {
                IntegratorKind::Restir(p) => p,
                _ => r,
            };
            let (cur, old) = (r.data(&scene.world), prev_restir.data(&before.world));
            let out = self.renderer.install(|| seq.frame(&cur, &old));
            let rgb = out
                .radiance
                .iter()
                .map(|l| l.to_array().map(|c| if c.is_finite() { c } else { 0.0 }))
                .collect();
            frame.image = Some(FilmImage {
                rgb,
                variance: None,
                bad_pixels: 0,
            });
        } else {
            let r = self.job.run(self.renderer, scene, self.progress, None)?;
            if self.job.shard.is_some() {
                frame.part = Some(r);
            } else {
                frame.image = Some(film_rgb(&r.film));
            }
        }
        frame.seconds = clock.elapsed().as_secs_f64();
        Ok(frame)
    }
}

impl Iterator for FrameSequence<'_> {
    type Item = Result<Frame, Error>;

    /// The next frame; `Err` of kind `Interrupted` once `Progress::cancel`
    /// is set (the frames before are complete).
    fn next(&mut self) -> Option<Result<Frame, Error>> {
        let f = self.frames.next()?;
        if self.progress.cancel.load(Ordering::Relaxed) {
            self.frames = f..f;
            return Some(Err(Error {
                kind: ErrorKind::Interrupted,
                message: format!("interrupted before frame {f}; earlier frames are done"),
            }));
        }
        let scene = match self.first.at_frame(f) {
            Ok(s) => s,
            Err(e) => {
                self.frames = f..f;
                return Some(Err(e.into()));
            }
        };
        let frame = self.render(f, scene);
        if let Ok(fr) = &frame {
            self.prev = Some(fr.scene.clone());
        }
        Some(frame)
    }
}

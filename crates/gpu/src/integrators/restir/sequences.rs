//! The restir drivers on the GPU: a static render (independent sequences,
//! each keeping its last frame, as the CPU's `fogbank render`), the last
//! frames of an animated scene's sequences, and one sequence rendered frame
//! by frame (`--frames`).

use super::frame_data::restir_of;
use super::frame_data::FrameGpu;
use super::kernels::{PassMs, RestirGpu};
use crate::accumulation::{after_passes, GpuRender, Observer};
use crate::{Gpu, GpuError};
use fogbank_render::integrators::restir::Reuse;
use fogbank_render::{Film, Progress, RenderOptions, Scene};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// `fogbank render --device gpu` of a static restir scene: as the CPU, each
/// of the `spp` passes is an independent sequence of `frames` frames whose
/// last frame is kept; sequences run `batch` at a time.
pub fn render(
    gpu: &Gpu,
    scene: &Scene,
    opts: &RenderOptions,
    progress: &Progress,
    mut after: Option<Observer<'_>>,
) -> Result<GpuRender, GpuError> {
    let restir = restir_of(scene)?;
    let p = &restir.params;
    let mut kernels = RestirGpu::new(gpu, scene, opts.spp.clamp(1, 64))?;
    let mut data = kernels.upload(gpu, scene)?;
    data.set_seed(gpu, opts.seed);
    let pixels = (scene.camera.width * scene.camera.height) as u64;
    let mut start = Instant::now();
    let mut interrupted = false;
    let (mut done, mut frames) = (0, 0);
    'sequences: while done < opts.spp {
        if opts.time_budget.is_some_and(|b| start.elapsed() >= b) {
            break;
        }
        let n = kernels.batch.min(opts.spp - done);
        kernels.start_sequences(done, n);
        for f in 0..p.frames {
            if progress.cancel.load(Ordering::Relaxed) {
                interrupted = true;
                break 'sequences;
            }
            kernels.frame(gpu, &data, &data, f, f + 1 == p.frames, p.reuse)?;
            frames += 1;
        }
        done += n;
        after_passes(progress, n, pixels, &mut after, &mut start, || {
            kernels.film(gpu)
        })?;
    }
    let seconds = start.elapsed().as_secs_f64();
    let t = kernels.times;
    let gpu_ms = gpu
        .timestamps
        .then_some(t.candidates + t.temporal + t.spatial + t.shading);
    Ok(GpuRender {
        film: kernels.film(gpu)?,
        seconds,
        gpu_ms,
        interrupted,
        upload_bytes: kernels.upload_bytes,
        // One submission per frame of a batch.
        submits: frames,
    })
}

/// The last frame of `sequences` independent sequences (seed `seed`) over
/// the built frames `frames` of an animated restir scene, frame i reusing
/// from frame i − 1, as a film (mean and variance over the sequences), with
/// the device time of each pass.
pub fn last_frames(
    gpu: &Gpu,
    frames: &[Scene],
    seed: u32,
    sequences: u32,
) -> Result<(Film, PassMs), GpuError> {
    let first = frames
        .first()
        .ok_or_else(|| GpuError("restir: no frames to render".into()))?;
    let reuse = restir_of(first)?.params.reuse;
    let mut kernels = RestirGpu::new(gpu, first, sequences.clamp(1, 64))?;
    let mut data = frames
        .iter()
        .map(|s| kernels.upload(gpu, s))
        .collect::<Result<Vec<_>, _>>()?;
    for d in &mut data {
        d.set_seed(gpu, seed);
    }
    let mut done = 0;
    while done < sequences {
        let n = kernels.batch.min(sequences - done);
        kernels.start_sequences(done, n);
        for f in 0..data.len() {
            let last = f + 1 == data.len();
            kernels.frame(
                gpu,
                &data[f],
                &data[f.saturating_sub(1)],
                f as u32,
                last,
                reuse,
            )?;
        }
        done += n;
    }
    Ok((kernels.film(gpu)?, kernels.times))
}

/// One ReSTIR sequence rendered frame by frame (`fogbank render --frames
/// --device gpu`): each frame reuses from the one before it, and its
/// shading is that frame's image.
pub struct SequenceGpu {
    kernels: RestirGpu,
    prev: Option<FrameGpu>,
    frame: u32,
    seed: u32,
    reuse: Reuse,
}

impl SequenceGpu {
    /// A sequence (index 0 of seed `seed`) of the restir scene `first`.
    pub fn new(gpu: &Gpu, first: &Scene, seed: u32) -> Result<SequenceGpu, GpuError> {
        let reuse = restir_of(first)?.params.reuse;
        let mut kernels = RestirGpu::new(gpu, first, 1)?;
        kernels.start_sequences(0, 1);
        Ok(SequenceGpu {
            kernels,
            prev: None,
            frame: 0,
            seed,
            reuse,
        })
    }

    /// Renders the next frame, `scene` (the sequence's scene at that frame).
    pub fn frame(&mut self, gpu: &Gpu, scene: &Scene) -> Result<Film, GpuError> {
        let mut cur = self.kernels.upload(gpu, scene)?;
        cur.set_seed(gpu, self.seed);
        self.kernels.clear_film(gpu);
        let prev = self.prev.as_ref().unwrap_or(&cur);
        self.kernels
            .frame(gpu, &cur, prev, self.frame, true, self.reuse)?;
        self.frame += 1;
        self.prev = Some(cur);
        self.kernels.film(gpu)
    }

    /// Device time of each pass so far.
    pub fn times(&self) -> PassMs {
        self.kernels.times
    }
}

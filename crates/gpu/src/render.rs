//! The progressive render loop on the GPU for the integrators with a WGSL
//! kernel (`transmittance`, `direct`, `volpath`, `point_mis`, `visopt`,
//! `ament`): the same image as the
//! CPU's (same scene, seed, sample indices and random streams), accumulated
//! on the device and read back once.

use crate::accumulation::{after_passes, read_film};
pub use crate::accumulation::{GpuRender, Observer};
use crate::kernel::Kernel;
use crate::kernel_setup::{self, Accumulators, KernelTimer, SceneGroups};
use crate::{Gpu, GpuError};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{Progress, RenderOptions, Scene};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Samples per pixel per dispatch: short dispatches keep the desktop
/// responsive and cancellation prompt.
const SAMPLES_PER_DISPATCH: u32 = 4;
const MAX_TIMED_DISPATCHES: u32 = 2048;

pub fn render(
    gpu: &Gpu,
    scene: &Scene,
    opts: &RenderOptions,
    progress: &Progress,
) -> Result<GpuRender, GpuError> {
    render_observed(gpu, scene, opts, progress, None)
}

/// [`render`], calling `after(film, seconds)` after every dispatch with the
/// film read back and the render time so far (the read-back is not
/// counted), for equal-time convergence curves.
pub fn render_observed(
    gpu: &Gpu,
    scene: &Scene,
    opts: &RenderOptions,
    progress: &Progress,
    after: Option<Observer<'_>>,
) -> Result<GpuRender, GpuError> {
    if let IntegratorKind::Restir(_) = scene.integrator {
        return crate::restir::render(gpu, scene, opts, progress, after);
    }
    render_kernel(gpu, scene, &Kernel::of(scene)?, opts, progress, after)
}

/// Runs `kernel` (as [`Kernel::of`] the scene's integrator gives it).
pub(crate) fn render_kernel(
    gpu: &Gpu,
    scene: &Scene,
    kernel: &Kernel,
    opts: &RenderOptions,
    progress: &Progress,
    mut after: Option<Observer<'_>>,
) -> Result<GpuRender, GpuError> {
    let groups = SceneGroups::upload(gpu, scene, kernel)?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let pixels = (w as u64) * (h as u64);
    let acc = Accumulators::new(gpu, pixels);
    let pipeline = kernel_setup::pipeline(gpu, scene, kernel, &groups, &acc.layout)?;
    let mut frame = kernel_setup::initial_frame(scene, kernel, opts);
    let band = groups.band_rows(h);
    let timer = KernelTimer::new(
        gpu,
        opts.spp.div_ceil(SAMPLES_PER_DISPATCH),
        MAX_TIMED_DISPATCHES,
    );
    let mut start = Instant::now();
    let mut interrupted = false;
    let (mut done, mut issued) = (0u32, 0u32);
    while done < opts.spp {
        if progress.cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        if opts.time_budget.is_some_and(|b| start.elapsed() >= b) {
            break;
        }
        let n = SAMPLES_PER_DISPATCH.min(opts.spp - done);
        frame.first_sample = done;
        frame.sample_count = n;
        // Bands of rows, one pass each (visopt's NEE-list scratch holds a
        // band); a write lands before the next submission, so each band is
        // submitted with its own frame.
        let bands = h.div_ceil(band);
        for b in 0..bands {
            frame.tile_y = b * band;
            gpu.queue
                .write_buffer(&acc.frame, 0, bytemuck::bytes_of(&frame));
            let mut enc = gpu.device.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("render"),
                    timestamp_writes: timer.as_ref().and_then(|t| t.writes(issued, b, bands)),
                });
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(1, &acc.group, &[]);
                groups.bind(&mut pass);
                pass.dispatch_workgroups(w.div_ceil(8), band.min(h - frame.tile_y).div_ceil(8), 1);
            }
            gpu.queue.submit([enc.finish()]);
        }
        // Wait, so progress, cancellation and the time budget see real time.
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError(format!("device poll failed: {e}")))?;
        issued += 1;
        done += n;
        after_passes(progress, n, pixels, &mut after, &mut start, || {
            read_film(gpu, w, h, &acc.sum, &acc.sq, &acc.lookups)
        })?;
    }
    let seconds = start.elapsed().as_secs_f64();
    let gpu_ms = match &timer {
        Some(t) => t.total_ms(gpu, issued)?,
        None => None,
    };
    Ok(GpuRender {
        film: read_film(gpu, w, h, &acc.sum, &acc.sq, &acc.lookups)?,
        seconds,
        gpu_ms,
        interrupted,
        upload_bytes: groups.bytes(),
    })
}

//! The progressive render loop on the GPU for the integrators with a
//! per-sample WGSL kernel (every port but `restir`'s): the same image as the
//! CPU's (same scene, seed, sample indices and random streams), accumulated
//! on the device and read back once.

use crate::accumulation::{after_passes, read_film, SAMPLES_PER_CHUNK};
pub use crate::accumulation::{GpuRender, Observer};
use crate::integrators::{port, Kernel};
use crate::kernel_setup::{self, Accumulators, KernelTimer, SceneGroups};
use crate::pin_stream::PinStreamPass;
use crate::{Gpu, GpuError};
use fogbank_render::{Progress, RenderOptions, Scene};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Invocations (pixel × chunk) one dispatch aims for: about four times
/// what an H100 or H200 keeps resident (132 SMs × 2048 threads), so a small
/// image runs many chunks of samples side by side instead of leaving the
/// device idle, and the waves' ragged ends (paths of unequal length)
/// overlap. On a lent H200 a 128² 1024-spp render took 100 / 89 ms at 2¹⁸,
/// 83 / 74 at 2¹⁹, 75 / 66 at 2²⁰ and the same beyond (docs/results/gpu.md).
const TARGET_INVOCATIONS: u64 = 1 << 20;

/// [`TARGET_INVOCATIONS`], or `FOGBANK_GPU_INVOCATIONS` when set (a tuning
/// knob for benchmarks: the image does not depend on it).
fn target_invocations() -> u64 {
    std::env::var("FOGBANK_GPU_INVOCATIONS")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .filter(|&n| n > 0)
        .unwrap_or(TARGET_INVOCATIONS)
}
/// At most this many bytes of chunk slots.
const MAX_SLOT_BYTES: u64 = 64 << 20;
const MAX_TIMED_DISPATCHES: u32 = 2048;
/// Submissions in flight before the host waits for the oldest.
const IN_FLIGHT: usize = 2;

/// How a render's samples are split into dispatches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Schedule {
    /// Chunks side by side up to [`TARGET_INVOCATIONS`], several
    /// submissions in flight (the default).
    Filled,
    /// One chunk per dispatch and a wait after each (the simplest
    /// scheduling; kept for observers, which read the film after every
    /// dispatch, and for the test that the two give the same image).
    Sequential,
}

impl Schedule {
    /// Dispatches submitted before the oldest is waited for.
    fn in_flight(self) -> usize {
        match self {
            Schedule::Filled => IN_FLIGHT,
            Schedule::Sequential => 1,
        }
    }
}

/// Chunks per dispatch for `band_pixels` pixels per band and `spp` samples
/// (no more chunk slots than the render's samples fill).
fn chunks_per_dispatch(schedule: Schedule, kernel: &Kernel, band_pixels: u64, spp: u32) -> u32 {
    // Per-pixel scratch (visopt's NEE lists): one chunk at a time.
    if schedule == Schedule::Sequential || !kernel.port.chunks_together() {
        return 1;
    }
    let by_target = target_invocations().div_ceil(band_pixels.max(1));
    let by_memory = MAX_SLOT_BYTES / (kernel_setup::SLOT_BYTES * band_pixels.max(1));
    let by_samples = spp.div_ceil(SAMPLES_PER_CHUNK) as u64;
    by_target.min(by_memory).min(by_samples).clamp(1, 4096) as u32
}

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
    let port = port(scene)?;
    if port.own_passes() {
        return port.render_passes(gpu, scene, opts, progress, after);
    }
    render_kernel(gpu, scene, &Kernel::of(scene)?, opts, progress, after)
}

/// Runs `kernel` (as [`Kernel::of`] the scene's integrator gives it): the
/// render of every port without passes of its own.
pub(crate) fn render_kernel(
    gpu: &Gpu,
    scene: &Scene,
    kernel: &Kernel,
    opts: &RenderOptions,
    progress: &Progress,
    after: Option<Observer<'_>>,
) -> Result<GpuRender, GpuError> {
    let schedule = match after {
        Some(_) => Schedule::Sequential,
        None => Schedule::Filled,
    };
    render_scheduled(gpu, scene, kernel, opts, progress, after, schedule)
}

/// Chunks and samples per dispatch. The pin stream (`streamed`) changes
/// the grids before every pass: one sample index a dispatch.
fn dispatch_size(
    streamed: bool,
    schedule: Schedule,
    kernel: &Kernel,
    band_pixels: u64,
    spp: u32,
) -> (u32, u32) {
    if streamed {
        return (1, 1);
    }
    let chunks = chunks_per_dispatch(schedule, kernel, band_pixels, spp);
    (chunks, chunks * SAMPLES_PER_CHUNK)
}

/// [`render_kernel`] with an explicit [`Schedule`]. The image is the same
/// for both: chunks of [`SAMPLES_PER_CHUNK`] samples merge into the film in
/// sample order either way.
pub(crate) fn render_scheduled(
    gpu: &Gpu,
    scene: &Scene,
    kernel: &Kernel,
    opts: &RenderOptions,
    progress: &Progress,
    mut after: Option<Observer<'_>>,
    schedule: Schedule,
) -> Result<GpuRender, GpuError> {
    let groups = SceneGroups::upload(gpu, scene, kernel)?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let pixels = (w as u64) * (h as u64);
    let band = groups.band_rows(h);
    let band_pixels = w as u64 * band.min(h) as u64;
    let stream = groups.group3.as_ref().and_then(|g| g.stream.as_ref());
    let (chunks, per_dispatch) =
        dispatch_size(stream.is_some(), schedule, kernel, band_pixels, opts.spp);
    let acc = Accumulators::new(gpu, pixels, chunks as u64 * band_pixels);
    let (main, merge) = kernel_setup::pipeline(gpu, scene, kernel, &groups, &acc.layout)?;
    let mut frame = kernel_setup::initial_frame(scene, kernel, opts);
    let timer = KernelTimer::new(gpu, opts.spp.div_ceil(per_dispatch), MAX_TIMED_DISPATCHES);
    let dispatch = Dispatch {
        gpu,
        acc: &acc,
        groups: &groups,
        main: &main,
        merge: &merge,
        band,
        timer: timer.as_ref(),
        stream,
    };
    let mut start = Instant::now();
    let mut interrupted = false;
    let (mut submitted, mut issued, mut submits) = (0u32, 0u32, 0u32);
    // Submitted dispatches not yet waited for: (last submission, samples).
    let mut in_flight = std::collections::VecDeque::new();
    let in_flight_limit = schedule.in_flight();
    loop {
        let cancelled = progress.cancel.load(Ordering::Relaxed);
        interrupted |= cancelled;
        let stop = cancelled || opts.time_budget.is_some_and(|b| start.elapsed() >= b);
        if !stop && submitted < opts.spp {
            let n = per_dispatch.min(opts.spp - submitted);
            let index = dispatch.submit_samples(&mut frame, submitted..submitted + n, issued);
            submits += h.div_ceil(band);
            in_flight.push_back((index, n));
            submitted += n;
            issued += 1;
        }
        let drain = stop || submitted >= opts.spp;
        if in_flight.is_empty() {
            break;
        }
        if in_flight.len() < in_flight_limit && !drain {
            continue;
        }
        // Wait for the oldest, so progress, cancellation and the time
        // budget see real time while the next one runs.
        let (index, n) = in_flight.pop_front().expect("in flight");
        wait_for(gpu, index)?;
        after_passes(progress, n, pixels, &mut after, &mut start, || {
            read_film(gpu, w, h, &acc.moments, &acc.lookups)
        })?;
    }
    let seconds = start.elapsed().as_secs_f64();
    Ok(GpuRender {
        film: read_film(gpu, w, h, &acc.moments, &acc.lookups)?,
        seconds,
        gpu_ms: timer.map_or(Ok(None), |t| t.total_ms(gpu, issued))?,
        interrupted,
        upload_bytes: groups.bytes(),
        submits,
    })
}

/// Blocks until submission `index` has run.
fn wait_for(gpu: &Gpu, index: wgpu::SubmissionIndex) -> Result<(), GpuError> {
    gpu.device
        .poll(wgpu::PollType::Wait {
            submission_index: Some(index),
            timeout: None,
        })
        .map(|_| ())
        .map_err(|e| GpuError(format!("device poll failed: {e}")))
}

/// One end of a timed span as a pass's timestamp writes.
fn pass_writes(
    at: Option<(&wgpu::QuerySet, u32)>,
    begin: bool,
) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
    at.map(|(query_set, i)| wgpu::ComputePassTimestampWrites {
        query_set,
        beginning_of_pass_write_index: begin.then_some(i),
        end_of_pass_write_index: (!begin).then_some(i),
    })
}

/// What one sample dispatch submits: the render and merge pipelines over
/// the scene's bind groups and the accumulators, band by band (`band`
/// rows at a time), timed when a timer is given.
struct Dispatch<'a> {
    gpu: &'a Gpu,
    acc: &'a Accumulators,
    groups: &'a SceneGroups,
    main: &'a wgpu::ComputePipeline,
    merge: &'a wgpu::ComputePipeline,
    band: u32,
    timer: Option<&'a KernelTimer>,
    /// The pin stream, which changes the grids before each sample index.
    stream: Option<&'a PinStreamPass>,
}

impl Dispatch<'_> {
    /// Submits sample indices `samples` (the `issued`-th dispatch), after
    /// the pin stream's grids for them.
    fn submit_samples(
        &self,
        frame: &mut crate::accumulation::Frame,
        samples: std::ops::Range<u32>,
        issued: u32,
    ) -> wgpu::SubmissionIndex {
        let n = samples.end - samples.start;
        frame.first_sample = samples.start;
        frame.sample_count = n;
        frame.chunks = n.div_ceil(SAMPLES_PER_CHUNK);
        if let Some(st) = self.stream {
            st.submit(self.gpu, &self.groups.media, samples.start);
        }
        self.submit(frame, issued)
    }

    /// Submits one dispatch of `frame` (its samples and chunks set; the
    /// `issued`-th dispatch): per band of rows, the chunks side by side and
    /// then their merge, each band in its own submission (a band's frame
    /// uniform lands before it). Returns the last submission.
    fn submit(&self, frame: &mut crate::accumulation::Frame, issued: u32) -> wgpu::SubmissionIndex {
        let Dispatch {
            gpu,
            acc,
            groups,
            main,
            merge,
            band,
            timer,
            ..
        } = *self;
        let (w, h) = (frame.width, frame.height);
        let bands = h.div_ceil(band);
        let mut index = None;
        for b in 0..bands {
            frame.tile_y = b * band;
            let rows = band.min(h - frame.tile_y);
            frame.band_pixels = w * rows;
            gpu.queue
                .write_buffer(&acc.frame, 0, bytemuck::bytes_of(frame));
            let mut enc = gpu.device.create_command_encoder(&Default::default());
            let (begin, end) = match timer.and_then(|t| t.writes(issued, b, bands)) {
                Some(t) => (
                    t.beginning_of_pass_write_index.map(|i| (t.query_set, i)),
                    t.end_of_pass_write_index.map(|i| (t.query_set, i)),
                ),
                None => (None, None),
            };
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("render"),
                    timestamp_writes: pass_writes(begin, true),
                });
                pass.set_pipeline(main);
                pass.set_bind_group(1, &acc.group, &[]);
                groups.bind(&mut pass);
                pass.dispatch_workgroups(w.div_ceil(8), rows.div_ceil(8), frame.chunks);
            }
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("merge"),
                    timestamp_writes: pass_writes(end, false),
                });
                pass.set_pipeline(merge);
                pass.set_bind_group(1, &acc.group, &[]);
                groups.bind(&mut pass);
                pass.dispatch_workgroups(frame.band_pixels.div_ceil(64), 1, 1);
            }
            index = Some(gpu.queue.submit([enc.finish()]));
        }
        index.expect("an image has at least one band")
    }
}

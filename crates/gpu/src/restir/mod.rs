//! `restir` on the GPU (seed 002 §5, Fig. 5): the passes of the CPU's
//! `restir::frame` as compute kernels over one shared reservoir buffer —
//! candidates → (reprojection, temporal reuse) → spatial reuse → final
//! shading → reduction into the accumulation buffers. WGSL in
//! `src/wgsl/restir/`, one file per pass, mirroring the CPU files.
//!
//! Independent sequences run side by side along the dispatch's z axis
//! (`batch` of them), so small images still fill the device; each pass
//! keys its random numbers by seed, pixel, sequence, frame and pass as the
//! CPU does. Reprojection runs with the previous frame's bind groups
//! (camera, medium placement, lights), the other passes with the current
//! frame's, so moving cameras, media placements and lights reuse as on the
//! CPU. Timestamp queries give the time of each pass.
//!
//! Velocity fields move reprojected points back as on the CPU (a grid, or
//! an affine field: a constant or the plume's).

#[cfg(test)]
mod kernel_test;
mod uniform;

use crate::accumulation::{frame_bind_group_layout, read_film, Frame, GpuRender, Observer};
use crate::contract::gpu_estimator;
use crate::lights::LightBuffers;
use crate::scene_buffers::SceneBuffers;
use crate::{shaders, Gpu, GpuError};
use fogbank_render::integrators::restir::{Restir, Reuse};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::world::velocity::Velocity;
use fogbank_render::{Film, Progress, RenderOptions, Scene};
use std::sync::atomic::Ordering;
use std::time::Instant;
pub use uniform::STORED_BYTES;
use uniform::{MipRecords, Regions, RestirUniform, VelocityGpu};

/// Reservoir regions: candidates, temporal output, previous frame's.
const REGIONS: u64 = 3;
/// The reservoir buffer is kept under this size when choosing the batch.
const RESERVOIR_BUDGET: u64 = 1 << 30;

/// Milliseconds of device time per pass, summed over the frames rendered.
#[derive(Clone, Copy, Debug, Default)]
pub struct PassMs {
    pub candidates: f64,
    /// Reprojection and temporal combination.
    pub temporal: f64,
    pub spatial: f64,
    /// Final shading and the reduction into the film.
    pub shading: f64,
    pub frames: u32,
}

const PASSES: [&str; 6] = [
    "candidates",
    "reproject",
    "temporal",
    "spatial",
    "shade",
    "reduce",
];

fn restir_of(scene: &Scene) -> Result<&Restir, GpuError> {
    match &scene.integrator {
        IntegratorKind::Restir(r) => Ok(r),
        _ => Err(GpuError(
            "the restir kernels render integrator `restir`".into(),
        )),
    }
}

/// One frame's data on the device: its media (with the mips), lights and
/// camera (bind groups 0–2).
pub struct FrameGpu {
    media: SceneBuffers,
    lights: LightBuffers,
    frame_buf: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    frame: Frame,
    velocity: VelocityGpu,
}

/// The restir kernels with their reservoir and accumulation buffers.
pub struct RestirGpu {
    pipelines: Vec<wgpu::ComputePipeline>,
    uniform: RestirUniform,
    uniform_buf: wgpu::Buffer,
    restir_group: wgpu::BindGroup,
    sum: wgpu::Buffer,
    sq: wgpu::Buffer,
    lookups: wgpu::Buffer,
    frame_layout: wgpu::BindGroupLayout,
    width: u32,
    height: u32,
    /// Sequences per dispatch.
    pub batch: u32,
    /// The previous frame's region of each batch position (None: none yet).
    prev: Option<u32>,
    queries: Option<(wgpu::QuerySet, wgpu::Buffer)>,
    pub times: PassMs,
    pub upload_bytes: u64,
}

impl RestirGpu {
    /// Kernels for the restir scene `scene` (its parameters and image
    /// size), running up to `max_batch` sequences per dispatch.
    pub fn new(gpu: &Gpu, scene: &Scene, max_batch: u32) -> Result<RestirGpu, GpuError> {
        let restir = restir_of(scene)?;
        let p = &restir.params;
        let est = gpu_estimator(p.estimator).ok_or_else(|| {
            GpuError(format!(
                "restir: shading estimator `{}` has no GPU kernel",
                p.estimator.name()
            ))
        })?;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let pixels = w as u64 * h as u64;
        let limit = gpu
            .device
            .limits()
            .max_storage_buffer_binding_size
            .min(RESERVOIR_BUDGET.max(REGIONS * pixels * STORED_BYTES));
        let fit = limit / (REGIONS * pixels * STORED_BYTES);
        if fit == 0 {
            return Err(GpuError(format!(
                "restir: {w}×{h} needs {} MiB of reservoirs, over the device's storage-buffer limit of {} MiB",
                (REGIONS * pixels * STORED_BYTES) >> 20,
                limit >> 20
            )));
        }
        let batch = (max_batch.max(1) as u64).min(fit).min(65_535) as u32;
        let device = &gpu.device;
        let zeroed = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let reservoirs = zeroed("reservoirs", REGIONS * batch as u64 * pixels * STORED_BYTES);
        let (sum, sq, lookups) = (
            zeroed("accum_sum", pixels * 16),
            zeroed("accum_sq", pixels * 16),
            zeroed("accum_lookups", pixels * 4),
        );
        let uniform_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("restir"),
            size: std::mem::size_of::<RestirUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let buffer_entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let restir_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("restir"),
            entries: &[
                buffer_entry(0, wgpu::BufferBindingType::Uniform),
                buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: false }),
            ],
        });
        let restir_group =
            gpu.bind_group_of("restir", &restir_layout, &[&uniform_buf, &reservoirs]);
        let frame_layout = frame_bind_group_layout(device);
        // The layouts of groups 0 and 2 are those every upload makes.
        let first = upload_frame(
            gpu,
            scene,
            &frame_layout,
            &sum,
            &sq,
            &lookups,
            est_frame(scene, &est),
        )?;
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("restir"),
            bind_group_layouts: &[
                Some(&first.media.bind_group_layout),
                Some(&frame_layout),
                Some(&first.lights.bind_group_layout),
                Some(&restir_layout),
            ],
            immediate_size: 0,
        });
        let module = gpu.checked("restir kernel", || {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("restir"),
                source: wgpu::ShaderSource::Wgsl(shaders::restir_kernel().into()),
            })
        })?;
        let constants = [("ESTIMATOR", est.id as f64)];
        let pipelines = PASSES
            .iter()
            .map(|entry| {
                gpu.checked(&format!("restir pipeline {entry}"), || {
                    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(entry),
                        layout: Some(&layout),
                        module: &module,
                        entry_point: Some(entry),
                        compilation_options: wgpu::PipelineCompilationOptions {
                            constants: &constants,
                            ..Default::default()
                        },
                        cache: None,
                    })
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let queries = gpu.timestamps.then(|| {
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("restir pass times"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * PASSES.len() as u32,
            });
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("restir timestamps"),
                size: 16 * PASSES.len() as u64,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            (set, resolve)
        });
        let mips = MipRecords {
            first_mip: first.media.extra_first,
            bc4: p.reuse_bc4.then_some(first.media.extra_first + 3),
        };
        Ok(RestirGpu {
            pipelines,
            uniform: RestirUniform::new(p, &mips, batch),
            uniform_buf,
            restir_group,
            sum,
            sq,
            lookups,
            frame_layout,
            width: w,
            height: h,
            batch,
            prev: None,
            queries,
            times: PassMs::default(),
            upload_bytes: first.media.bytes,
        })
    }

    /// Uploads one frame's scene (a frame of the sequence being rendered:
    /// same integrator parameters and image size).
    pub fn upload(&self, gpu: &Gpu, scene: &Scene) -> Result<FrameGpu, GpuError> {
        let restir = restir_of(scene)?;
        let (w, h) = (scene.camera.width, scene.camera.height);
        if (w, h) != (self.width, self.height) {
            return Err(GpuError(format!(
                "restir: a frame of {w}×{h} in a sequence of {}×{}",
                self.width, self.height
            )));
        }
        let est = gpu_estimator(restir.params.estimator)
            .ok_or_else(|| GpuError("restir: shading estimator has no GPU kernel".into()))?;
        upload_frame(
            gpu,
            scene,
            &self.frame_layout,
            &self.sum,
            &self.sq,
            &self.lookups,
            est_frame(scene, &est),
        )
    }

    /// Starts new sequences `first..first + n` (n ≤ `batch`; the next frame
    /// has no previous one).
    pub fn start_sequences(&mut self, first: u32, n: u32) {
        self.uniform.first_sequence = first;
        self.uniform.batch = n.clamp(1, self.batch);
        self.prev = None;
    }

    /// Renders frame `frame_index` of the current sequences with `cur` and
    /// the previous frame's `prev`, adding its shading to the film when
    /// `accumulate` (every frame's lookups are counted).
    pub fn frame(
        &mut self,
        gpu: &Gpu,
        cur: &FrameGpu,
        prev: &FrameGpu,
        frame_index: u32,
        accumulate: bool,
        reuse: Reuse,
    ) -> Result<(), GpuError> {
        let plan = Regions::plan(self.prev, reuse.temporal, reuse.spatial);
        plan.apply(&mut self.uniform);
        cur.velocity.apply(&mut self.uniform);
        self.uniform.frame_index = frame_index;
        self.uniform.accumulate = accumulate as u32;
        gpu.queue
            .write_buffer(&self.uniform_buf, 0, bytemuck::bytes_of(&self.uniform));
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let (gx, gy) = (self.width.div_ceil(8), self.height.div_ceil(8));
        let b = self.batch.min(self.uniform.batch);
        // (pass, frame data, z) in the order they run; pass q writes
        // timestamps 2q and 2q + 1.
        let mut order: Vec<(usize, &FrameGpu, u32)> = vec![(0, cur, b)];
        if plan.temporal.is_some() {
            order.push((1, prev, b));
            order.push((2, cur, b));
        }
        if plan.spatial.is_some() {
            order.push((3, cur, b));
        }
        order.push((4, cur, b));
        order.push((5, cur, 1));
        for (q, &(pass, data, z)) in order.iter().enumerate() {
            let tw = self
                .queries
                .as_ref()
                .map(|(set, _)| wgpu::ComputePassTimestampWrites {
                    query_set: set,
                    beginning_of_pass_write_index: Some(2 * q as u32),
                    end_of_pass_write_index: Some(2 * q as u32 + 1),
                });
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(PASSES[pass]),
                timestamp_writes: tw,
            });
            cp.set_pipeline(&self.pipelines[pass]);
            cp.set_bind_group(0, &data.media.bind_group, &[]);
            cp.set_bind_group(1, &data.frame_group, &[]);
            cp.set_bind_group(2, &data.lights.bind_group, &[]);
            cp.set_bind_group(3, &self.restir_group, &[]);
            cp.dispatch_workgroups(gx, gy, z);
        }
        if let Some((set, resolve)) = &self.queries {
            enc.resolve_query_set(set, 0..2 * order.len() as u32, resolve, 0);
        }
        gpu.queue.submit([enc.finish()]);
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError(format!("device poll failed: {e}")))?;
        if let Some((_, resolve)) = &self.queries {
            let raw = gpu.read_back(resolve)?;
            let ticks: &[u64] = bytemuck::cast_slice(&raw);
            let period = gpu.queue.get_timestamp_period() as f64 * 1e-6;
            let t = &mut self.times;
            for (q, &(pass, _, _)) in order.iter().enumerate() {
                let ms = ticks[2 * q + 1].saturating_sub(ticks[2 * q]) as f64 * period;
                match pass {
                    0 => t.candidates += ms,
                    1 | 2 => t.temporal += ms,
                    3 => t.spatial += ms,
                    _ => t.shading += ms,
                }
            }
        }
        self.times.frames += 1;
        self.prev = Some(plan.last);
        Ok(())
    }

    /// Empties the accumulation buffers.
    pub fn clear_film(&self, gpu: &Gpu) {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for b in [&self.sum, &self.sq, &self.lookups] {
            enc.clear_buffer(b, 0, None);
        }
        gpu.queue.submit([enc.finish()]);
    }

    /// The accumulation buffers as a film.
    pub fn film(&self, gpu: &Gpu) -> Result<Film, GpuError> {
        read_film(
            gpu,
            self.width,
            self.height,
            &self.sum,
            &self.sq,
            &self.lookups,
        )
    }
}

/// The frame uniform of `scene` with the shading estimator's options.
fn est_frame(scene: &Scene, est: &crate::contract::GpuEstimator) -> Frame {
    let (origin, forward, right, up, tan_half) = scene.camera.basis();
    let v4 = |v: glam::Vec3| [v.x, v.y, v.z, 0.0];
    Frame {
        cam_origin: v4(origin),
        cam_forward: v4(forward),
        cam_right: v4(right),
        cam_up: v4(up),
        background: [0.0; 4],
        tan_half,
        width: scene.camera.width,
        height: scene.camera.height,
        seed: 0,
        first_sample: 0,
        sample_count: 0,
        media_count: scene.media.len() as u32,
        pixel_jitter: 0,
        est_samples: est.samples,
        est_step: est.step,
        est_flags: est.flags,
        max_depth: 0,
        rr_depth: 0,
        sampler: 0,
        mis_samples: 0,
        integrator_flags: 0,
        pad: [0; 3],
    }
}

fn upload_frame(
    gpu: &Gpu,
    scene: &Scene,
    frame_layout: &wgpu::BindGroupLayout,
    sum: &wgpu::Buffer,
    sq: &wgpu::Buffer,
    lookups: &wgpu::Buffer,
    frame: Frame,
) -> Result<FrameGpu, GpuError> {
    let restir = restir_of(scene)?;
    let full = &scene.media[0].medium;
    let mut extra: Vec<&fogbank_volume::Medium> =
        (1..=3).map(|l| restir.mips.level(full, l)).collect();
    if restir.params.reuse_bc4 {
        extra.push(restir.mips.reuse(full, restir.params.reuse_mip));
    }
    let sm = &scene.media[0];
    let fields: Vec<&fogbank_render::world::field::Field> = match &sm.velocity {
        Some(Velocity::Grid { field, .. }) => vec![field],
        _ => vec![],
    };
    let media = SceneBuffers::upload_with(gpu, scene, &extra, &fields)?;
    let velocity = VelocityGpu::new(
        sm.velocity.as_ref(),
        media.field_first.first().copied().unwrap_or(0),
        scene.world.frame_dt,
    );
    let lights = LightBuffers::upload(gpu, scene, &media.properties)?;
    let frame_buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("frame"),
        size: std::mem::size_of::<Frame>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    gpu.queue
        .write_buffer(&frame_buf, 0, bytemuck::bytes_of(&frame));
    let frame_group = gpu.bind_group_of("frame", frame_layout, &[&frame_buf, sum, sq, lookups]);
    Ok(FrameGpu {
        media,
        lights,
        frame_buf,
        frame_group,
        frame,
        velocity,
    })
}

impl FrameGpu {
    /// Sets the seed the frame's passes key their random numbers with.
    pub fn set_seed(&mut self, gpu: &Gpu, seed: u32) {
        self.frame.seed = seed;
        gpu.queue
            .write_buffer(&self.frame_buf, 0, bytemuck::bytes_of(&self.frame));
    }
}

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
    let mut done = 0;
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
        }
        done += n;
        progress
            .samples_done
            .fetch_add(n as u64 * pixels, Ordering::Relaxed);
        progress.passes_done.fetch_add(n as u64, Ordering::Relaxed);
        if let Some(f) = after.as_mut() {
            let observing = Instant::now();
            let film = kernels.film(gpu)?;
            f(&film, (observing - start).as_secs_f64());
            start += observing.elapsed();
        }
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

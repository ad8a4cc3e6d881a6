//! The restir kernels (one pipeline per pass) with their reservoir buffer,
//! uniform and accumulation buffers, and one frame of one batch of
//! sequences: which reservoir regions each pass uses, the passes in order
//! (reprojection with the previous frame's bind groups), per-pass device
//! time from timestamp queries.

use super::frame_data::{restir_of, shading_estimator, upload_frame, FrameGpu};
use super::uniform::{MipRecords, Regions, RestirUniform, STORED_BYTES};
use crate::accumulation::{frame_bind_group_layout, read_film};
use crate::context::buffer_entry;
use crate::pipelines::PipelineSpec;
use crate::{Gpu, GpuError};
use fogbank_render::integrators::restir::Reuse;
use fogbank_render::{Film, Scene};

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

pub(super) const PASSES: [&str; 6] = [
    "candidates",
    "reproject",
    "temporal",
    "spatial",
    "shade",
    "reduce",
];

/// The restir kernels with their reservoir and accumulation buffers.
pub struct RestirGpu {
    pipelines: Vec<wgpu::ComputePipeline>,
    uniform: RestirUniform,
    uniform_buf: wgpu::Buffer,
    restir_group: wgpu::BindGroup,
    moments: wgpu::Buffer,
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
        let p = &restir_of(scene)?.params;
        let est = shading_estimator(scene)?;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let pixels = w as u64 * h as u64;
        let batch = batch_for(gpu, w, h, max_batch)?;
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
        let (moments, lookups) = (
            zeroed("accum_moments", pixels * 32),
            zeroed("accum_lookups", pixels * 4),
        );
        let uniform_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("restir"),
            size: std::mem::size_of::<RestirUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let restir_layout = restir_bind_group_layout(gpu);
        let restir_group =
            gpu.bind_group_of("restir", &restir_layout, &[&uniform_buf, &reservoirs]);
        let frame_layout = frame_bind_group_layout(gpu);
        // The layouts of groups 0 and 2 are those every upload makes.
        let first = upload_frame(gpu, scene, &frame_layout, &moments, &lookups)?;
        let layouts = [
            Some(&first.media.bind_group_layout),
            Some(&frame_layout),
            Some(&first.lights.bind_group_layout),
            Some(&restir_layout),
        ];
        let mips = MipRecords {
            first_mip: first.media.extra_first,
            bc4: p.reuse_bc4.then_some(first.media.extra_first + 3),
        };
        Ok(RestirGpu {
            pipelines: pipelines(
                gpu,
                &layouts,
                est.id,
                scene.world.surfaces.is_some(),
                restir_of(scene)?.lights.bvh().is_some(),
            )?,
            uniform: RestirUniform::new(p, &mips, batch),
            uniform_buf,
            restir_group,
            moments,
            lookups,
            frame_layout,
            width: w,
            height: h,
            batch,
            prev: None,
            queries: timestamp_queries(gpu),
            times: PassMs::default(),
            upload_bytes: first.media.bytes,
        })
    }

    /// Uploads one frame's scene (a frame of the sequence being rendered:
    /// same integrator parameters and image size).
    pub fn upload(&self, gpu: &Gpu, scene: &Scene) -> Result<FrameGpu, GpuError> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        if (w, h) != (self.width, self.height) {
            return Err(GpuError(format!(
                "restir: a frame of {w}×{h} in a sequence of {}×{}",
                self.width, self.height
            )));
        }
        upload_frame(gpu, scene, &self.frame_layout, &self.moments, &self.lookups)
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
        let passes: Vec<usize> = order.iter().map(|o| o.0).collect();
        self.add_pass_times(gpu, &passes)?;
        self.times.frames += 1;
        self.prev = Some(plan.last);
        Ok(())
    }

    /// Adds the device time of the frame's passes (`passes[q]` ran as the
    /// q-th, with timestamps 2q and 2q + 1) to [`RestirGpu::times`].
    fn add_pass_times(&mut self, gpu: &Gpu, passes: &[usize]) -> Result<(), GpuError> {
        let Some((_, resolve)) = &self.queries else {
            return Ok(());
        };
        let raw = gpu.read_back(resolve)?;
        let ticks: &[u64] = bytemuck::cast_slice(&raw);
        let period = gpu.queue.get_timestamp_period() as f64 * 1e-6;
        let t = &mut self.times;
        for (q, &pass) in passes.iter().enumerate() {
            let ms = ticks[2 * q + 1].saturating_sub(ticks[2 * q]) as f64 * period;
            match pass {
                0 => t.candidates += ms,
                1 | 2 => t.temporal += ms,
                3 => t.spatial += ms,
                _ => t.shading += ms,
            }
        }
        Ok(())
    }

    /// Empties the accumulation buffers.
    pub fn clear_film(&self, gpu: &Gpu) {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for b in [&self.moments, &self.lookups] {
            enc.clear_buffer(b, 0, None);
        }
        gpu.queue.submit([enc.finish()]);
    }

    /// The accumulation buffers as a film.
    pub fn film(&self, gpu: &Gpu) -> Result<Film, GpuError> {
        read_film(gpu, self.width, self.height, &self.moments, &self.lookups)
    }
}

/// Sequences per dispatch: at most `max_batch`, as many as keep the
/// reservoirs within the budget and the device's binding limit.
fn batch_for(gpu: &Gpu, w: u32, h: u32, max_batch: u32) -> Result<u32, GpuError> {
    let per_sequence = REGIONS * w as u64 * h as u64 * STORED_BYTES;
    let limit = gpu
        .device
        .limits()
        .max_storage_buffer_binding_size
        .min(RESERVOIR_BUDGET.max(per_sequence));
    let fit = limit / per_sequence;
    if fit == 0 {
        return Err(GpuError(format!(
            "restir: {w}×{h} needs {} MiB of reservoirs, over the device's storage-buffer limit of {} MiB",
            per_sequence >> 20,
            limit >> 20
        )));
    }
    Ok((max_batch.max(1) as u64).min(fit).min(65_535) as u32)
}

/// Bind group 3: the restir uniform and the reservoir buffer.
fn restir_bind_group_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    gpu.bind_group_layout(
        "restir",
        &[
            buffer_entry(0, wgpu::BufferBindingType::Uniform),
            buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: false }),
        ],
    )
}

/// One pipeline per pass, with the shading estimator `ESTIMATOR`, in a
/// scene with shapes their occlusion (`OCCLUDERS`, occluders.wgsl), and
/// whether lights are picked through a light BVH (`LIGHT_BVH`).
fn pipelines(
    gpu: &Gpu,
    layouts: &[Option<&wgpu::BindGroupLayout>],
    estimator: u32,
    occluders: bool,
    light_bvh: bool,
) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
    let source = super::source::source();
    PASSES
        .iter()
        .map(|entry| {
            gpu.compute_pipeline(&PipelineSpec {
                label: "restir",
                source: &source,
                entry,
                constants: &[
                    ("ESTIMATOR", estimator as f64),
                    ("OCCLUDERS", occluders as u32 as f64),
                    // surfaces.wgsl's shapes (restir/surface.wgsl's vertices).
                    (
                        "INTEGRATOR_FLAGS",
                        if occluders {
                            crate::contract::INTEGRATOR_SURFACES
                        } else {
                            0
                        } as f64,
                    ),
                    ("LIGHT_BVH", light_bvh as u32 as f64),
                ],
                layouts: Some(layouts),
            })
        })
        .collect()
}

/// Begin and end timestamps of every pass of a frame, when the device has them.
fn timestamp_queries(gpu: &Gpu) -> Option<(wgpu::QuerySet, wgpu::Buffer)> {
    gpu.timestamps.then(|| {
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("restir pass times"),
            ty: wgpu::QueryType::Timestamp,
            count: 2 * PASSES.len() as u32,
        });
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("restir timestamps"),
            size: 16 * PASSES.len() as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        (set, resolve)
    })
}

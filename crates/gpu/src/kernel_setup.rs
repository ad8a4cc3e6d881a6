//! What one per-sample kernel needs before its first dispatch: the scene's
//! bind groups (media; lights; the integrator's group 3), the frame uniform
//! and accumulation buffers, the compute pipeline, and timestamp queries
//! for its device time.

use crate::accumulation::{frame_bind_group_layout, Frame};
use crate::integrators::plugin::Group3;
use crate::integrators::Kernel;
use crate::lights::LightBuffers;
use crate::pipelines::PipelineSpec;
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
use fogbank_render::{RenderOptions, Scene};

/// The scene's bind groups 0, 2 and 3.
pub(crate) struct SceneGroups {
    pub(crate) media: SceneBuffers,
    pub(crate) lights: Option<LightBuffers>,
    /// The integrator's own (pin grids; Lerzer and Dachsbacher 2025's data).
    pub(crate) group3: Option<Group3>,
}

impl SceneGroups {
    pub(crate) fn upload(gpu: &Gpu, scene: &Scene, kernel: &Kernel) -> Result<Self, GpuError> {
        let fields = kernel.port.fields(scene);
        let media = SceneBuffers::upload_with(gpu, scene, &[], &fields)?;
        let lights = if kernel.params.scatter {
            let sampler = kernel.port.light_sampler(scene);
            Some(LightBuffers::upload(gpu, scene, &sampler, &media.grids)?)
        } else {
            None
        };
        let group3 = kernel.port.group3(gpu, scene, &kernel.params, &media)?;
        Ok(SceneGroups {
            media,
            lights,
            group3,
        })
    }

    /// Rows per dispatch: a band when the kernel has per-pixel scratch.
    pub(crate) fn band_rows(&self, height: u32) -> u32 {
        (self.group3.as_ref())
            .and_then(|g| g.band_rows)
            .unwrap_or(height)
            .max(1)
    }

    pub(crate) fn bytes(&self) -> u64 {
        self.media.bytes + self.group3.as_ref().map_or(0, |g| g.bytes)
    }

    /// Binds groups 0, 2 and 3 (group 1 is the frame's).
    pub(crate) fn bind(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_bind_group(0, &self.media.bind_group, &[]);
        if let Some(l) = &self.lights {
            pass.set_bind_group(2, &l.bind_group, &[]);
        }
        if let Some(g) = &self.group3 {
            pass.set_bind_group(3, &g.bind_group, &[]);
        }
    }
}

/// Group 1: the frame uniform and the device accumulation buffers.
pub(crate) struct Accumulators {
    pub(crate) frame: wgpu::Buffer,
    /// Per pixel (mean, n) and (M2, dropped samples).
    pub(crate) moments: wgpu::Buffer,
    pub(crate) lookups: wgpu::Buffer,
    pub(crate) layout: wgpu::BindGroupLayout,
    pub(crate) group: wgpu::BindGroup,
}

/// Bytes of one chunk slot: (mean, n), (M2, non-finite), (lookups).
pub(crate) const SLOT_BYTES: u64 = 48;

impl Accumulators {
    /// For `pixels` pixels and `slots` chunk slots.
    pub(crate) fn new(gpu: &Gpu, pixels: u64, slots: u64) -> Accumulators {
        let device = &gpu.device;
        let frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<Frame>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let zeroed = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let moments = zeroed("accum_moments", pixels * 32);
        let lookups = zeroed("accum_lookups", pixels * 4);
        let chunks = zeroed("accum_chunks", slots.max(1) * SLOT_BYTES);
        let layout = frame_bind_group_layout(gpu);
        let group = gpu.bind_group_of("frame", &layout, &[&frame, &moments, &lookups, &chunks]);
        Accumulators {
            frame,
            moments,
            lookups,
            layout,
            group,
        }
    }
}

/// The kernel's compute pipelines over `groups` and the frame layout:
/// `main` (the samples of each chunk) and `merge` (the chunks into the film).
pub(crate) fn pipeline(
    gpu: &Gpu,
    scene: &Scene,
    kernel: &Kernel,
    groups: &SceneGroups,
    frame_layout: &wgpu::BindGroupLayout,
) -> Result<(wgpu::ComputePipeline, wgpu::ComputePipeline), GpuError> {
    let source = kernel.source();
    let layouts = [
        Some(&groups.media.bind_group_layout),
        Some(frame_layout),
        groups.lights.as_ref().map(|l| &l.bind_group_layout),
        groups.group3.as_ref().map(|g| &g.layout),
    ];
    let constants = kernel.constants();
    let entry = |name| {
        gpu.compute_pipeline(&PipelineSpec {
            label: scene.integrator.name(),
            source: &source,
            entry: name,
            constants: &constants,
            layouts: Some(&layouts),
        })
    };
    Ok((entry("main")?, entry("merge")?))
}

/// The frame uniform before the first dispatch.
pub(crate) fn initial_frame(scene: &Scene, kernel: &Kernel, opts: &RenderOptions) -> Frame {
    let k = &kernel.params;
    let b = k.background;
    Frame {
        background: [b.x, b.y, b.z, 0.0],
        seed: opts.seed,
        pixel_jitter: scene.pixel_jitter as u32,
        max_depth: k.max_depth,
        rr_depth: k.rr_depth,
        mis_samples: k.mis_samples,
        march_step: k.pins.march_step,
        pin_mask_iterations: k.pins.grid.mask_iterations,
        ..Frame::of_scene(scene, &k.est)
    }
}

/// Timestamp queries around each dispatch (the device time of a render).
pub(crate) struct KernelTimer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
}

impl KernelTimer {
    /// For `dispatches` dispatches, if the device has timestamp queries
    /// and there are not too many.
    pub(crate) fn new(gpu: &Gpu, dispatches: u32, most: u32) -> Option<KernelTimer> {
        if !gpu.timestamps || dispatches == 0 || dispatches > most {
            return None;
        }
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("kernel time"),
            ty: wgpu::QueryType::Timestamp,
            count: 2 * dispatches,
        });
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: 16 * dispatches as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Some(KernelTimer { set, resolve })
    }

    /// The writes of dispatch `i`'s pass `b` of `bands`: its time spans
    /// the first pass's start to the last pass's end.
    pub(crate) fn writes(
        &self,
        i: u32,
        b: u32,
        bands: u32,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        (b == 0 || b + 1 == bands).then(|| wgpu::ComputePassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: (b == 0).then_some(2 * i),
            end_of_pass_write_index: (b + 1 == bands).then_some(2 * i + 1),
        })
    }

    /// Milliseconds summed over the first `issued` dispatches.
    pub(crate) fn total_ms(&self, gpu: &Gpu, issued: u32) -> Result<Option<f64>, GpuError> {
        if issued == 0 {
            return Ok(None);
        }
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        enc.resolve_query_set(&self.set, 0..2 * issued, &self.resolve, 0);
        gpu.queue.submit([enc.finish()]);
        let raw = gpu.read_back(&self.resolve)?;
        let ticks: &[u64] = bytemuck::cast_slice(&raw[..16 * issued as usize]);
        let period = gpu.queue.get_timestamp_period() as f64;
        let ticks: f64 = ticks
            .chunks(2)
            .map(|c| c[1].saturating_sub(c[0]) as f64)
            .sum();
        Ok(Some(ticks * period * 1e-6))
    }
}

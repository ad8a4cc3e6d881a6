//! The wgpu device: adapter selection, limits, timestamp support.

use crate::pipelines::{PipelineCache, PipelineSpec};
use std::fmt;

#[derive(Debug, Clone)]
pub struct GpuError(pub String);

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for GpuError {}

/// A device and its queue. Clones are handles to the same device and share
/// its built pipelines ([`crate::pipelines`]).
#[derive(Clone)]
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// Timestamp queries inside compute passes are available (`gpu_ms`).
    pub timestamps: bool,
    /// Most bytes of per-invocation scratch a kernel may allocate (visopt's
    /// NEE lists); kernels that need more render in bands of rows.
    pub scratch_budget: u64,
    pub(crate) pipelines: std::sync::Arc<PipelineCache>,
}

/// The default [`Gpu::scratch_budget`] (Lerzer and Dachsbacher 2025's static scratch is 156 MB).
pub const SCRATCH_BUDGET: u64 = 128 << 20;

impl Gpu {
    /// The first high-performance adapter wgpu finds (Vulkan, Metal, DX12 or
    /// GL), with the largest storage buffers it allows.
    pub fn new() -> Result<Gpu, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            // Vulkan, Metal, DX12; GL only on request (its probing is noisy
            // on headless machines and it has no timestamp queries).
            desc.backends = wgpu::Backends::PRIMARY;
        }
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|e| {
            GpuError(format!(
                "no GPU adapter found ({e}); on Linux without a GPU, Mesa's lavapipe \
                 (Debian package mesa-vulkan-drivers) provides a Vulkan device on the CPU"
            ))
        })?;
        let info = adapter.get_info();
        let supported = adapter.features();
        let timestamps = supported.contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = wgpu::Features::empty();
        if timestamps {
            features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let al = adapter.limits();
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: al.max_storage_buffer_binding_size,
            max_buffer_size: al.max_buffer_size,
            max_storage_buffers_per_shader_stage: al.max_storage_buffers_per_shader_stage.min(16),
            ..wgpu::Limits::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("fogbank"),
            required_features: features,
            required_limits: limits,
            ..Default::default()
        }))
        .map_err(|e| GpuError(format!("{}: cannot open the device: {e}", info.name)))?;
        Ok(Gpu {
            device,
            queue,
            info,
            timestamps,
            scratch_budget: SCRATCH_BUDGET,
            pipelines: Default::default(),
        })
    }

    /// "name (backend, driver)" for logs and stats.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {} {})",
            self.info.name, self.info.backend, self.info.driver, self.info.driver_info
        )
    }

    /// Whether the device is a CPU rasteriser such as lavapipe (its times
    /// say nothing about a GPU).
    pub fn is_cpu(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// Runs `f` (creating shader modules, pipelines) and turns a validation
    /// error into a `GpuError` instead of wgpu's default panic.
    pub fn checked<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        crate::pipelines::validated(&self.device, what, f).map_err(GpuError)
    }

    /// The bind group layout with `entries`: the same object for equal
    /// entries, so that pipelines over it are shared.
    pub fn bind_group_layout(
        &self,
        label: &str,
        entries: &[wgpu::BindGroupLayoutEntry],
    ) -> wgpu::BindGroupLayout {
        self.pipelines
            .bind_group_layout(&self.device, label, entries)
    }

    /// The compute pipeline `spec` describes, built on its first request
    /// on this device ([`crate::pipelines`]). Validation errors (a WGSL
    /// error, a layout mismatch) are errors, not panics, and are not kept.
    pub fn compute_pipeline(&self, spec: &PipelineSpec) -> Result<wgpu::ComputePipeline, GpuError> {
        self.pipelines
            .compute_pipeline(&self.device, spec)
            .map_err(GpuError)
    }

    /// How many handles to this device are alive (this one included).
    pub(crate) fn handles(&self) -> usize {
        std::sync::Arc::strong_count(&self.pipelines)
    }

    /// How many pipelines this device has built (not counting those it
    /// handed out again).
    pub fn pipelines_built(&self) -> u64 {
        self.pipelines.built()
    }

    /// A bind group whose binding i is the whole of `buffers[i]`.
    pub fn bind_group_of(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        buffers: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &buffers
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource: b.as_entire_binding(),
                })
                .collect::<Vec<_>>(),
        })
    }

    pub fn storage_buffer(&self, label: &str, bytes: &[u8]) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        // Zero-sized bindings are invalid; pad empty arrays to one word.
        let padded;
        let contents = if bytes.is_empty() {
            padded = [0u8; 16];
            &padded[..]
        } else {
            bytes
        };
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
    }

    /// Copies `buffer` back to the host (blocking).
    pub fn read_back(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let size = buffer.size();
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([enc.finish()]);
        let slice = staging.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError(format!("device poll failed: {e}")))?;
        rx.recv()
            .map_err(|e| GpuError(format!("readback: {e}")))?
            .map_err(|e| GpuError(format!("readback: {e}")))?;
        let data = slice
            .get_mapped_range()
            .map_err(|e| GpuError(format!("readback: {e}")))?
            .to_vec();
        staging.unmap();
        Ok(data)
    }
}

/// A compute-stage layout entry for a whole buffer of kind `ty` (uniform,
/// storage read-only or read-write) at `binding`.
pub(crate) fn buffer_entry(
    binding: u32,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

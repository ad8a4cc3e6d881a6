//! Hansen 2025's pins on the GPU: every medium's grid gathered in a compute
//! pass (`pin_gather_kernel.wgsl`, one invocation per 5D cell, the stream
//! Pcg32(seed, cell) of the CPU's `PinGrid::gather`) as
//! [`PinParams::plan`] lays the grids out — rigid instances share one —
//! and bind group 3 of the scatter kernel (`tracking.wgsl`) that reads them.
//! With pins off the group holds one absent record, so the kernel is the
//! same for every `volpath`.

use crate::context::buffer_entry;
use crate::pin_kernel::grid_kernel;
use crate::pin_stream::PinStreamPass;
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
use bytemuck::{Pod, Zeroable};
use fogbank_render::integrators::shared::pin_params::{GridPlan, PinParams};
use fogbank_render::Scene;
use wgpu::util::DeviceExt;

/// A grid read back: its medium and [Ĩ, t_min bits] per pin.
pub type GatheredGrid = (usize, Vec<[u32; 2]>);

/// One medium's grid as WGSL `PinGridGpu` reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct PinGridGpu {
    pub(crate) offset: u32,
    pub(crate) positions: u32,
    pub(crate) phi: u32,
    pub(crate) theta: u32,
    pub(crate) jitter_position: f32,
    pub(crate) jitter_direction: f32,
    pub(crate) step: f32,
    pub(crate) present: u32,
}

/// WGSL `GatherParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct GatherParams {
    pub(crate) seed: [u32; 2],
    pub(crate) medium: u32,
    pub(crate) count: u32,
}

/// The scatter kernel's group 3.
pub(crate) struct PinBuffers {
    pub(crate) layout: wgpu::BindGroupLayout,
    pub(crate) bind_group: wgpu::BindGroup,
    /// (medium, first pin, pin count) of every gathered grid.
    pub(crate) gathered: Vec<(usize, u32, u32)>,
    pins: wgpu::Buffer,
    /// Bytes of the pins (instances share theirs).
    pub(crate) bytes: u64,
    /// The stream before every pass (`pin_grid.stream`), when on.
    pub(crate) stream: Option<PinStreamPass>,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(binding, wgpu::BufferBindingType::Storage { read_only })
}

impl PinBuffers {
    /// The grids of `params` gathered on the device (`None`: pins off, one
    /// absent record).
    pub(crate) fn build(
        gpu: &Gpu,
        scene: &Scene,
        media: &SceneBuffers,
        params: Option<&PinParams>,
    ) -> Result<PinBuffers, GpuError> {
        let plan = match params {
            Some(p) => p.plan(&scene.world).map_err(|e| GpuError(e.0))?,
            None => None,
        };
        let mut records = vec![PinGridGpu::default(); scene.media.len().max(1)];
        let mut gathered = Vec::new();
        let mut seeds = Vec::new();
        let mut total = 0u64;
        for (i, p) in plan.iter().flatten().enumerate() {
            records[i] = match *p {
                GridPlan::Shared(j) => records[j],
                GridPlan::Own { spec, seed } => {
                    let count = spec.pin_count().map_err(GpuError)?;
                    let r = PinGridGpu {
                        offset: total as u32,
                        positions: spec.positions,
                        phi: spec.phi,
                        theta: spec.theta,
                        jitter_position: spec.jitter_position,
                        jitter_direction: spec.jitter_direction,
                        step: spec.step,
                        present: 1,
                    };
                    gathered.push((i, total as u32, count as u32));
                    seeds.push(seed);
                    total += count;
                    r
                }
            };
        }
        let bytes = total * 8;
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        if bytes > limit {
            return Err(GpuError(format!(
                "pin grids: {} MiB exceed the device's storage-buffer limit of {} MiB \
                 (lower integrator.pin_grid.positions or memory_ratio)",
                bytes >> 20,
                limit >> 20
            )));
        }
        let device = &gpu.device;
        let grids = gpu.storage_buffer("pin_grids", bytemuck::cast_slice(&records));
        let pins = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pins"),
            size: bytes.max(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        if !gathered.is_empty() {
            gather(gpu, media, &grids, &pins, &gathered, &seeds)?;
        }
        // As the CPU's `PinParams::stream`: unquantised pins read no grid.
        let stream = match params {
            Some(p) if p.grid.stream > 0 && !p.grid.unquantised && !gathered.is_empty() => {
                let owners: Vec<usize> = gathered.iter().map(|g| g.0).collect();
                Some(PinStreamPass::new(
                    gpu, media, &grids, &pins, &owners, &p.grid,
                )?)
            }
            _ => None,
        };
        let layout =
            gpu.bind_group_layout("pins", &[storage_entry(0, true), storage_entry(1, true)]);
        let bind_group = gpu.bind_group_of("pins", &layout, &[&grids, &pins]);
        Ok(PinBuffers {
            layout,
            bind_group,
            gathered,
            pins,
            bytes,
            stream,
        })
    }

    /// The gathered grids read back: (medium, [mask, t_min bits] per pin).
    pub(crate) fn read_back(&self, gpu: &Gpu) -> Result<Vec<GatheredGrid>, GpuError> {
        let raw = gpu.read_back(&self.pins)?;
        let all: &[[u32; 2]] = bytemuck::cast_slice(&raw);
        Ok(self
            .gathered
            .iter()
            .map(|&(m, first, n)| (m, all[first as usize..(first + n) as usize].to_vec()))
            .collect())
    }
}

/// Runs the gather kernel once per grid (in 2D dispatches past 65535
/// workgroups) and waits for it.
fn gather(
    gpu: &Gpu,
    media: &SceneBuffers,
    grids: &wgpu::Buffer,
    pins: &wgpu::Buffer,
    gathered: &[(usize, u32, u32)],
    seeds: &[u64],
) -> Result<(), GpuError> {
    let device = &gpu.device;
    let (layout, pipeline) = grid_kernel(
        gpu,
        media,
        "pin gather",
        &crate::shaders::pin_gather_kernel(),
    )?;
    let mut enc = device.create_command_encoder(&Default::default());
    for (&(medium, _, count), &seed) in gathered.iter().zip(seeds) {
        let params = GatherParams {
            seed: [seed as u32, (seed >> 32) as u32],
            medium: medium as u32,
            count,
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("pin gather params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let group = gpu.bind_group_of("pin gather", &layout, &[&uniform, grids, pins]);
        let workgroups = count.div_ceil(64);
        let x = workgroups.min(65535);
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &media.bind_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups(x, workgroups.div_ceil(x), 1);
    }
    gpu.queue.submit([enc.finish()]);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError(format!("device poll failed: {e}")))?;
    Ok(())
}

/// For tests and tools: the grids `scene`'s `volpath` gathers on the
/// device, read back as (medium, [Ĩ, t_min bits] per pin) — the CPU's
/// `PinGrid::gather` up to rounding of the marched transmittances.
pub fn gathered_pins(gpu: &Gpu, scene: &Scene) -> Result<Vec<GatheredGrid>, GpuError> {
    let fogbank_render::integrators::IntegratorKind::VolPath(v) = &scene.integrator else {
        return Err(GpuError("pins belong to integrator `volpath`".into()));
    };
    let media = SceneBuffers::upload(gpu, scene)?;
    PinBuffers::build(gpu, scene, &media, Some(&v.pins))?.read_back(gpu)
}

/// For tests and tools: the grids of `scene`'s `volpath` after the device's
/// gather and the streams of passes 0..`passes` (`pin_grid.stream`), read
/// back as [`gathered_pins`] reads them.
pub fn streamed_pins(gpu: &Gpu, scene: &Scene, passes: u32) -> Result<Vec<GatheredGrid>, GpuError> {
    let fogbank_render::integrators::IntegratorKind::VolPath(v) = &scene.integrator else {
        return Err(GpuError("pins belong to integrator `volpath`".into()));
    };
    let media = SceneBuffers::upload(gpu, scene)?;
    let buffers = PinBuffers::build(gpu, scene, &media, Some(&v.pins))?;
    let stream = buffers
        .stream
        .as_ref()
        .ok_or_else(|| GpuError("integrator.pin_grid.stream is off".into()))?;
    for pass in 0..passes {
        stream.submit(gpu, &media, pass);
    }
    buffers.read_back(gpu)
}

#[cfg(test)]
mod pins_kernel_test {
    use super::*;
    use crate::shaders::{self, check_layout};
    use std::mem::{offset_of, size_of};

    /// naga's full validation and SPIR-V generation of `entry` (what the
    /// Vulkan backend does; its writer has panicked on constructs the
    /// validator accepts).
    fn compiles_to_spirv(src: &str, constants: &[(&str, f64)]) {
        let module = naga::front::wgsl::parse_str(src)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(src)));
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(src)));
        let mut c = naga::back::PipelineConstants::default();
        for (k, v) in constants {
            c.insert(k.to_string(), *v);
        }
        let stage = naga::ShaderStage::Compute;
        let (m, i) = naga::back::pipeline_constants::process_overrides(
            &module,
            &info,
            Some((stage, "main")),
            &c,
        )
        .unwrap();
        let options = naga::back::spv::PipelineOptions {
            shader_stage: stage,
            entry_point: "main".into(),
        };
        naga::back::spv::write_vec(&m, &i, &Default::default(), Some(&options)).unwrap();
    }

    #[test]
    fn gather_stream_and_scatter_kernels_compile_to_spirv() {
        compiles_to_spirv(&shaders::pin_gather_kernel(), &[]);
        compiles_to_spirv(&shaders::pin_stream_kernel(), &[]);
        compiles_to_spirv(&shaders::scatter_kernel(), &[("ESTIMATOR", 2.0)]);
    }

    #[test]
    fn wgsl_pin_structs_have_the_rust_layout() {
        let gather = shaders::pin_gather_kernel();
        check_layout(
            &gather,
            "PinGridGpu",
            size_of::<PinGridGpu>(),
            &[
                ("offset", offset_of!(PinGridGpu, offset)),
                ("positions", offset_of!(PinGridGpu, positions)),
                ("phi", offset_of!(PinGridGpu, phi)),
                ("theta", offset_of!(PinGridGpu, theta)),
                ("jitter_position", offset_of!(PinGridGpu, jitter_position)),
                ("jitter_direction", offset_of!(PinGridGpu, jitter_direction)),
                ("step", offset_of!(PinGridGpu, step)),
                ("present", offset_of!(PinGridGpu, present)),
            ],
        );
        check_layout(
            &gather,
            "GatherParams",
            size_of::<GatherParams>(),
            &[
                ("seed", offset_of!(GatherParams, seed)),
                ("medium", offset_of!(GatherParams, medium)),
                ("count", offset_of!(GatherParams, count)),
            ],
        );
    }
}

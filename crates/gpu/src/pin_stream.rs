//! Hansen 2025's pin stream on the GPU (`pin_grid.stream`): before every pass,
//! `pin_stream_kernel.wgsl` streams R pins into each gathered grid, pin i
//! of grid g from Pcg32(`stream_seed`(seed, g's owner, pass), i) as the
//! CPU's `shared::pin_stream` draws it. The render loop then runs one
//! sample index per dispatch, so each pass reads the grids its stream left.

use crate::pin_kernel::grid_kernel;
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};
use bytemuck::{Pod, Zeroable};
use fogbank_estimators::pins::MIN_STREAM_SPACING;
use fogbank_render::integrators::shared::pin_params::PinGridParams;
use fogbank_render::integrators::shared::pin_stream::stream_seed;

/// WGSL `StreamParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct StreamParams {
    pub(crate) seed: [u32; 2],
    pub(crate) medium: u32,
    pub(crate) count: u32,
    pub(crate) spacing: f32,
    pub(crate) min_spacing: f32,
    pub(crate) _pad: [u32; 2],
}

/// One grid's stream: its owner medium, parameter uniform and bind group.
struct GridStream {
    owner: u32,
    uniform: wgpu::Buffer,
    group: wgpu::BindGroup,
}

/// The stream kernel and a bind group per gathered grid.
pub(crate) struct PinStreamPass {
    pipeline: wgpu::ComputePipeline,
    grids: Vec<GridStream>,
    count: u32,
    spacing: f32,
    grid_seed: u64,
}

impl PinStreamPass {
    /// The stream of `params` into the grids owned by media `owners`,
    /// whose records are `records` and pins `pins` (as `PinBuffers` holds
    /// them).
    pub(crate) fn new(
        gpu: &Gpu,
        media: &SceneBuffers,
        records: &wgpu::Buffer,
        pins: &wgpu::Buffer,
        owners: &[usize],
        params: &PinGridParams,
    ) -> Result<PinStreamPass, GpuError> {
        let (layout, pipeline) = grid_kernel(
            gpu,
            media,
            "pin stream",
            &crate::shaders::pin_stream_kernel(),
        )?;
        let grids = owners
            .iter()
            .map(|&owner| {
                let uniform = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("pin stream params"),
                    size: std::mem::size_of::<StreamParams>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let group = gpu.bind_group_of("pin stream", &layout, &[&uniform, records, pins]);
                GridStream {
                    owner: owner as u32,
                    uniform,
                    group,
                }
            })
            .collect();
        Ok(PinStreamPass {
            pipeline,
            grids,
            count: params.stream,
            spacing: params.stream_spacing,
            grid_seed: params.seed,
        })
    }

    /// Submits pass `pass`'s stream into every grid; the queue orders it
    /// after the dispatches submitted before and before those after.
    pub(crate) fn submit(&self, gpu: &Gpu, media: &SceneBuffers, pass: u32) {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let workgroups = self.count.div_ceil(64);
        let x = workgroups.clamp(1, 65535);
        for g in &self.grids {
            let seed = stream_seed(self.grid_seed, g.owner as usize, pass);
            let params = StreamParams {
                seed: [seed as u32, (seed >> 32) as u32],
                medium: g.owner,
                count: self.count,
                spacing: self.spacing,
                min_spacing: MIN_STREAM_SPACING,
                _pad: [0; 2],
            };
            gpu.queue
                .write_buffer(&g.uniform, 0, bytemuck::bytes_of(&params));
            let mut cpass = enc.begin_compute_pass(&Default::default());
            cpass.set_pipeline(&self.pipeline);
            cpass.set_bind_group(0, &media.bind_group, &[]);
            cpass.set_bind_group(1, &g.group, &[]);
            cpass.dispatch_workgroups(x, workgroups.div_ceil(x), 1);
        }
        gpu.queue.submit([enc.finish()]);
    }
}

#[cfg(test)]
mod pin_stream_kernel_test {
    use super::*;
    use crate::shaders::{self, check_layout};
    use std::mem::{offset_of, size_of};

    #[test]
    fn wgsl_stream_params_have_the_rust_layout() {
        check_layout(
            &shaders::pin_stream_kernel(),
            "StreamParams",
            size_of::<StreamParams>(),
            &[
                ("seed", offset_of!(StreamParams, seed)),
                ("medium", offset_of!(StreamParams, medium)),
                ("count", offset_of!(StreamParams, count)),
                ("spacing", offset_of!(StreamParams, spacing)),
                ("min_spacing", offset_of!(StreamParams, min_spacing)),
                ("_pad", offset_of!(StreamParams, _pad)),
            ],
        );
    }
}

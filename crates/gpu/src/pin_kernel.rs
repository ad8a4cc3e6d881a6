//! What Hansen 2025's grid-writing kernels share (the gather of `pins.rs` and
//! the stream of `pin_stream.rs`): their bind-group layout and pipeline.

use crate::context::buffer_entry;
use crate::pipelines::PipelineSpec;
use crate::scene_buffers::SceneBuffers;
use crate::{Gpu, GpuError};

/// A kernel that writes pin grids (gather, stream): group 0 the media,
/// group 1 its parameters, the grids' records and the pins (writable).
pub(crate) fn grid_kernel(
    gpu: &Gpu,
    media: &SceneBuffers,
    label: &str,
    source: &str,
) -> Result<(wgpu::BindGroupLayout, wgpu::ComputePipeline), GpuError> {
    let layout = gpu.bind_group_layout(
        label,
        &[
            buffer_entry(0, wgpu::BufferBindingType::Uniform),
            buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: true }),
            buffer_entry(2, wgpu::BufferBindingType::Storage { read_only: false }),
        ],
    );
    let pipeline = gpu.compute_pipeline(&PipelineSpec {
        label,
        source,
        entry: "main",
        constants: &[],
        layouts: Some(&[Some(&media.bind_group_layout), Some(&layout)]),
    })?;
    Ok((layout, pipeline))
}

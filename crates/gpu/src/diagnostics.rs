//! Kernels that exist to test the WGSL ports against the CPU bit for bit.

use crate::{shaders, Gpu, GpuError};
use fogbank_math::SampleKey;
use wgpu::util::DeviceExt;

/// The first `count` words of each key's PCG32 stream, computed on the GPU.
pub fn rng_streams(gpu: &Gpu, keys: &[SampleKey], count: u32) -> Result<Vec<u32>, GpuError> {
    let device = &gpu.device;
    let key_words: Vec<[u32; 4]> = keys
        .iter()
        .map(|k| [k.seed, k.pixel, k.sample, k.dimension])
        .collect();
    let keys_buf = gpu.storage_buffer("keys", bytemuck::cast_slice(&key_words));
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out"),
        size: (keys.len() as u64 * count as u64 * 4).max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("params"),
        contents: bytemuck::cast_slice(&[keys.len() as u32, count, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("rng_streams"),
        source: wgpu::ShaderSource::Wgsl(
            format!("{}\n{}", shaders::RNG, shaders::RNG_STREAMS_KERNEL).into(),
        ),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("rng_streams"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("rng_streams"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: keys_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: out.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: params.as_entire_binding(),
            },
        ],
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((keys.len() as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([enc.finish()]);
    let bytes = gpu.read_back(&out)?;
    Ok(bytemuck::cast_slice(&bytes)[..keys.len() * count as usize].to_vec())
}

/// One pin query along a unit-cube ray (WGSL `ChordQuery`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ChordQuery {
    pub o: [f32; 3],
    pub t_start: f32,
    pub d: [f32; 3],
    pub max_len: f32,
    pub mask: u32,
    pub t_min: f32,
    pub u: f32,
    pub iterations: u32,
}

/// Each query answered by pins.wgsl: [popcount exponent (u32::MAX: no
/// chord), MSB distance with `mask` as the collision mask and `u`,
/// `Chord::distance` from Pcg32::new(query index, 7), T̃] — floats as bits,
/// −1 for no collision.
pub fn chord_queries(gpu: &Gpu, queries: &[ChordQuery]) -> Result<Vec<[u32; 4]>, GpuError> {
    let device = &gpu.device;
    let q = gpu.storage_buffer("queries", bytemuck::cast_slice(queries));
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("answers"),
        size: (queries.len() as u64 * 16).max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let source = [
        shaders::estimators().as_str(),
        shaders::PINS,
        shaders::CHORD_QUERIES_KERNEL,
    ]
    .join("\n");
    let module = gpu.checked("chord queries kernel", || {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("chord_queries"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
    })?;
    let pipeline = gpu.checked("chord queries pipeline", || {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("chord_queries"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        })
    })?;
    // Group 0 (the media, unused here) is empty but must be bound.
    let empty = gpu.bind_group_of("empty", &pipeline.get_bind_group_layout(0), &[]);
    let group = gpu.bind_group_of(
        "chord_queries",
        &pipeline.get_bind_group_layout(1),
        &[&q, &out],
    );
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &empty, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups((queries.len() as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([enc.finish()]);
    let bytes = gpu.read_back(&out)?;
    Ok(bytemuck::cast_slice(&bytes)[..queries.len()].to_vec())
}

/// One ray for [`bvh_queries`]: origin and t_max, direction.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BvhQuery {
    pub o: [f32; 3],
    pub t_max: f32,
    pub d: [f32; 3],
    pub pad: f32,
}

/// Each query answered by bvh.wgsl against `accel`'s nodes and leaf-order
/// triangles: [leaf slot of the closest hit (u32::MAX: none), t bits, b1
/// bits, 1 if the any-hit query hit].
pub fn bvh_queries(
    gpu: &Gpu,
    accel: &fogbank_geometry::MeshAccel,
    queries: &[BvhQuery],
) -> Result<Vec<[u32; 4]>, GpuError> {
    let device = &gpu.device;
    // An empty hierarchy is one node with an empty box (bindings cannot be
    // empty): the root test fails and nothing is hit.
    let empty = [fogbank_geometry::BvhNode {
        min: [f32::INFINITY; 3],
        count: 0,
        max: [f32::NEG_INFINITY; 3],
        index: 0,
    }];
    let nodes = if accel.bvh.nodes.is_empty() {
        &empty[..]
    } else {
        &accel.bvh.nodes[..]
    };
    let mut tris: Vec<[f32; 12]> = accel
        .leaf_corners()
        .iter()
        .map(|c| {
            let mut t = [0.0f32; 12];
            // A non-finite corner: a point (never hit, as on the CPU).
            if c.iter().all(|p| p.is_finite()) {
                for (k, p) in c.iter().enumerate() {
                    t[4 * k..4 * k + 3].copy_from_slice(&p.to_array());
                }
            }
            t
        })
        .collect();
    if tris.is_empty() {
        tris.push([0.0; 12]);
    }
    let n = gpu.storage_buffer("bvh_nodes", bytemuck::cast_slice(nodes));
    let t = gpu.storage_buffer("surface_triangles", bytemuck::cast_slice(&tris));
    let q = gpu.storage_buffer("bvh_queries", bytemuck::cast_slice(queries));
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("bvh_answers"),
        size: (queries.len() as u64 * 16).max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let source = [shaders::BVH, shaders::BVH_QUERIES_KERNEL].join("\n");
    let module = gpu.checked("bvh queries kernel", || {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("bvh_queries"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
    })?;
    let pipeline = gpu.checked("bvh queries pipeline", || {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("bvh_queries"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        })
    })?;
    let group = gpu.bind_group_of(
        "bvh_queries",
        &pipeline.get_bind_group_layout(0),
        &[&n, &t, &q, &out],
    );
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((queries.len() as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([enc.finish()]);
    let bytes = gpu.read_back(&out)?;
    Ok(bytemuck::cast_slice(&bytes)[..queries.len()].to_vec())
}

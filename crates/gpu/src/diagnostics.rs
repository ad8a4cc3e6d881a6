//! Kernels that exist to test the WGSL ports against the CPU bit for bit.

use crate::{shaders, Gpu, GpuError};
use fogbank_math::SampleKey;
use wgpu::util::DeviceExt;

/// The first `count` words of each key's PCG32 stream, computed on the GPU.
pub fn rng_streams(gpu: &Gpu, keys: &[SampleKey], count: u32) -> Result<Vec<u32>, GpuError> {
    let key_words: Vec<[u32; 4]> = keys
        .iter()
        .map(|k| [k.seed, k.pixel, k.sample, k.dimension])
        .collect();
    let keys_buf = gpu.storage_buffer("keys", bytemuck::cast_slice(&key_words));
    let out = output_buffer(gpu, "out", keys.len() as u64 * count as u64 * 4);
    let params = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::cast_slice(&[keys.len() as u32, count, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let source = format!("{}\n{}", shaders::RNG, shaders::RNG_STREAMS_KERNEL);
    let bytes = run_once(
        gpu,
        "rng_streams",
        source,
        &[&[&keys_buf, &out, &params]],
        keys.len(),
        &out,
    )?;
    Ok(bytemuck::cast_slice(&bytes)[..keys.len() * count as usize].to_vec())
}

/// A storage buffer the kernel writes and the CPU reads back.
fn output_buffer(gpu: &Gpu, label: &str, bytes: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Compiles `source` (entry point `main`, workgroups of 64), binds
/// `groups[g][i]` at group g binding i, runs one invocation per item and
/// reads `out` back.
fn run_once(
    gpu: &Gpu,
    label: &str,
    source: String,
    groups: &[&[&wgpu::Buffer]],
    items: usize,
    out: &wgpu::Buffer,
) -> Result<Vec<u8>, GpuError> {
    let pipeline = gpu.compute_pipeline(&crate::pipelines::PipelineSpec {
        label,
        source: &source,
        entry: "main",
        constants: &[],
        layouts: None,
    })?;
    let bind: Vec<wgpu::BindGroup> = groups
        .iter()
        .enumerate()
        .map(|(g, buffers)| {
            gpu.bind_group_of(label, &pipeline.get_bind_group_layout(g as u32), buffers)
        })
        .collect();
    dispatch(gpu, &pipeline, &bind.iter().collect::<Vec<_>>(), items, out)
}

/// Runs `pipeline` once per item with `bind[g]` at group g and reads `out`
/// back.
fn dispatch(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    bind: &[&wgpu::BindGroup],
    items: usize,
    out: &wgpu::Buffer,
) -> Result<Vec<u8>, GpuError> {
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        for (g, b) in bind.iter().enumerate() {
            pass.set_bind_group(g as u32, *b, &[]);
        }
        pass.dispatch_workgroups((items as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([enc.finish()]);
    gpu.read_back(out)
}

/// Each query (point xyz, u in w) answered by lights.wgsl and
/// light_bvh.wgsl with `scene`'s lights for a point in a medium:
/// [`pick_light`'s light (u32::MAX: none), its pmf bits, `light_pmf_at`
/// of that light bits, 0] — to compare with `LightSampler::pick` and
/// `pmf`.
pub fn light_picks(
    gpu: &Gpu,
    scene: &fogbank_render::Scene,
    queries: &[[f32; 4]],
) -> Result<Vec<[u32; 4]>, GpuError> {
    let grids = vec![crate::medium_records::MediumGrids::default(); scene.media.len()];
    let sampler = crate::integrators::light_sampler(scene);
    let lights = crate::lights::LightBuffers::upload(gpu, scene, &sampler, &grids)?;
    let q = gpu.storage_buffer("pick_queries", bytemuck::cast_slice(queries));
    let out = output_buffer(gpu, "pick_answers", queries.len() as u64 * 16);
    let source = [
        shaders::estimators().as_str(),
        shaders::FRAME,
        shaders::MIS,
        shaders::PHASE,
        shaders::LIGHTS,
        shaders::SHAPE_LIGHTS,
        shaders::PROPERTIES,
        shaders::LIGHT_BVH,
        shaders::LIGHT_PICKS_KERNEL,
    ]
    .join("\n");
    let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let empty = gpu.bind_group_layout("empty", &[]);
    let io = gpu.bind_group_layout("light_picks", &[storage(0, true), storage(1, false)]);
    let layouts = [
        Some(&empty),
        Some(&empty),
        Some(&lights.bind_group_layout),
        Some(&io),
    ];
    let pipeline = gpu.compute_pipeline(&crate::pipelines::PipelineSpec {
        label: "light_picks",
        source: &source,
        entry: "main",
        constants: &[(
            "LIGHT_BVH",
            crate::integrators::has_light_bvh(scene) as u32 as f64,
        )],
        layouts: Some(&layouts),
    })?;
    let none = gpu.bind_group_of("empty", &empty, &[]);
    let io_group = gpu.bind_group_of("light_picks", &io, &[&q, &out]);
    let bind = [&none, &none, &lights.bind_group, &io_group];
    let bytes = dispatch(gpu, &pipeline, &bind, queries.len(), &out)?;
    Ok(bytemuck::cast_slice(&bytes)[..queries.len()].to_vec())
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
    let q = gpu.storage_buffer("queries", bytemuck::cast_slice(queries));
    let out = output_buffer(gpu, "answers", queries.len() as u64 * 16);
    let source = [
        shaders::estimators().as_str(),
        shaders::PINS,
        shaders::CHORD_QUERIES_KERNEL,
    ]
    .join("\n");
    // Group 0 (the media, unused here) is empty but must be bound.
    let bytes = run_once(
        gpu,
        "chord_queries",
        source,
        &[&[], &[&q, &out]],
        queries.len(),
        &out,
    )?;
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
    let nodes = crate::surfaces::node_words(accel)?;
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
    let n = gpu.storage_buffer("bvh_nodes", bytemuck::cast_slice(&nodes));
    let t = gpu.storage_buffer("surface_triangles", bytemuck::cast_slice(&tris));
    // Finite t_max, as the kernels pass (F32_INF): shader compilers may
    // assume infinities away.
    let finite: Vec<BvhQuery> = queries
        .iter()
        .map(|q| BvhQuery {
            t_max: q.t_max.min(f32::MAX),
            ..*q
        })
        .collect();
    let q = gpu.storage_buffer("bvh_queries", bytemuck::cast_slice(&finite));
    let out = output_buffer(gpu, "bvh_answers", queries.len() as u64 * 16);
    let source = [
        &crate::contract::wgsl_prelude(),
        shaders::FLOAT,
        shaders::BVH,
        shaders::ANALYTIC_SHAPES,
        shaders::BVH_QUERIES_KERNEL,
    ]
    .join("\n");
    let bytes = run_once(
        gpu,
        "bvh_queries",
        source,
        &[&[&n, &t, &q, &out]],
        queries.len(),
        &out,
    )?;
    Ok(bytemuck::cast_slice(&bytes)[..queries.len()].to_vec())
}

//! Bind group 2 of the scattering kernels: light records with their
//! selection CDF ([`records`], read by `wgsl/lights.wgsl`), the header and
//! environment map with its sampling CDFs ([`environment`]), each medium's
//! albedo, phase and emission ([`crate::medium_records`], read by
//! `wgsl/properties.wgsl`), the light BVH, and the surfaces
//! ([`crate::surfaces`]).

pub(crate) mod environment;
pub(crate) mod records;

use crate::contract::v4;
use crate::medium_records::{shading_records, MediumGrids};
use crate::{Gpu, GpuError};
use fogbank_render::lights::sample::{LightSampler, Vertex};
use fogbank_render::Scene;
use records::{LightGpu, Selection};
use wgpu::util::DeviceExt;

pub struct LightBuffers {
    pub bind_group_layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
}

impl LightBuffers {
    /// Bind group 2 for `scene`: the light records with `sampler`'s
    /// selection (the integrator's, which the GPU mirrors), the header with
    /// the environment map, the `shading` buffer (medium records, blackbody
    /// table, light BVH) and the surfaces. `grids`: per medium, where its
    /// property grids are ([`crate::scene_buffers::SceneBuffers::grids`]).
    pub fn upload(
        gpu: &Gpu,
        scene: &Scene,
        sampler: &LightSampler,
        grids: &[MediumGrids],
    ) -> Result<LightBuffers, GpuError> {
        let pickable = !sampler.cdf(Vertex::Medium).is_empty();
        let (mut env, map) = environment::environment(scene, pickable)?;
        let records = light_records(scene, sampler);
        let mut shading = shading_records(scene, grids);
        if let Some(b) = sampler.bvh() {
            env.bvh_first = b.first as u32;
            env.bvh_nodes = shading.len() as u32;
            shading.extend(light_bvh_nodes(b)?);
        }
        let surfaces = crate::surfaces::SurfaceBuffers::upload(gpu, scene)?;
        let buffers = [
            gpu.storage_buffer("lights", bytemuck::cast_slice(&records)),
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("env"),
                    contents: bytemuck::bytes_of(&env),
                    usage: wgpu::BufferUsages::UNIFORM,
                }),
            gpu.storage_buffer("env_rgb", bytemuck::cast_slice(&map.rgb)),
            gpu.storage_buffer("env_cdf", bytemuck::cast_slice(&map.cdf)),
            gpu.storage_buffer("shading", bytemuck::cast_slice(&shading)),
        ];
        let [lights, env, rgb, cdf, shading] = &buffers;
        let bufs = [
            lights,
            env,
            rgb,
            cdf,
            shading,
            &surfaces.nodes,
            &surfaces.data,
        ];
        Ok(bind(gpu, &bufs))
    }
}

/// Every light's record with its selection data (`records`' table).
fn light_records(scene: &Scene, sampler: &LightSampler) -> Vec<LightGpu> {
    // A light's CDF entry and pmf for points of kind `at`.
    let pick = |i: usize, at| {
        let c = sampler.cdf(at).get(i).copied().unwrap_or(1.0);
        [c, sampler.cdf_pmf(i, at)]
    };
    (scene.lights.iter().enumerate())
        .map(|(i, l)| {
            let trail = (sampler.bvh())
                .filter(|b| b.holds(i))
                .map_or(0, |b| b.trails[i - b.first]);
            let selection = Selection {
                trail,
                medium: pick(i, Vertex::Medium),
                surface: pick(i, Vertex::Surface),
            };
            records::pack(l, selection)
        })
        .collect()
}

/// The bind group over `bufs` (binding 1, the header, a uniform; the rest
/// read-only storage).
fn bind(gpu: &Gpu, bufs: &[&wgpu::Buffer; 7]) -> LightBuffers {
    let entry = |binding: u32| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: if binding == 1 {
                wgpu::BufferBindingType::Uniform
            } else {
                wgpu::BufferBindingType::Storage { read_only: true }
            },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let entries: Vec<_> = (0..bufs.len() as u32).map(entry).collect();
    let bind_group_layout = gpu.bind_group_layout("lights", &entries);
    let bind_group = gpu.bind_group_of("lights", &bind_group_layout, bufs);
    LightBuffers {
        bind_group_layout,
        bind_group,
    }
}

/// The light BVH's nodes for `light_bvh.wgsl`: three vec4s each of its
/// `Importance`, (centre, φ), (cone axis, cos θ_o), (r², d²_min, sin θ_o,
/// index as an exact float: the second child, or −(light + 1) for a leaf).
fn light_bvh_nodes(b: &fogbank_render::lights::bvh::LightBvh) -> Result<Vec<[f32; 4]>, GpuError> {
    if b.nodes.len() >= 1 << 24 {
        return Err(GpuError(format!(
            "{} emitting triangles: the GPU's light BVH takes fewer than 2^23",
            b.trails.len()
        )));
    }
    Ok((b.nodes.iter())
        .flat_map(|n| {
            let index = if n.leaf {
                -(n.index as f32 + 1.0)
            } else {
                n.index as f32
            };
            let i = &n.importance;
            [
                v4(i.centre, i.phi),
                v4(i.w, i.cos_theta_o),
                [i.r2, i.d2_min, i.sin_theta_o, index],
            ]
        })
        .collect())
}

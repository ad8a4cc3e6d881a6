//! Bind group 2 of the scattering kernels: light records with their
//! selection CDF, the environment map with its sampling CDFs, each
//! medium's albedo, phase and emission (`wgsl/lights.wgsl`,
//! `wgsl/properties.wgsl`), and the surfaces ([`crate::surfaces`]).

use crate::{Gpu, GpuError};
use bytemuck::{Pod, Zeroable};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::lights::sample::{LightSampler, Vertex};
use fogbank_render::lights::Light;
use fogbank_render::Scene;
use wgpu::util::DeviceExt;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct LightGpu {
    pub(crate) kind: u32,
    /// Emitting triangles in the light BVH: the bit trail from its root
    /// (`LightBvh::trails`).
    pub(crate) trail: u32,
    /// `LightSampler`'s CDF entry and pmf for points on surfaces (`d.zw`:
    /// for points in media).
    pub(crate) surface: [f32; 2],
    pub(crate) a: [f32; 4],
    pub(crate) b: [f32; 4],
    pub(crate) c: [f32; 4],
    pub(crate) d: [f32; 4],
    /// Area lights: the second edge (disks: the second half-axis).
    pub(crate) e: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct EnvParams {
    pub(crate) to_local: [[f32; 4]; 3],
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) light_count: u32,
    pub(crate) integral: f32,
    pub(crate) pickable: u32,
    /// Where the medium extensions and the blackbody table start in the
    /// `shading` buffer (after one (albedo, g) per medium).
    pub(crate) props_ext: u32,
    pub(crate) props_blackbody: u32,
    /// Lights before this index may be environments (none after: the
    /// emitting triangles of shapes follow the scene's lights).
    pub(crate) environments: u32,
    /// 1: read the map bilinearly (Mitsuba's lookup).
    pub(crate) bilinear: u32,
    /// Lights from this index on are picked through the light BVH
    /// (`light_count`: no tree), whose nodes start at this vec4 of the
    /// `shading` buffer.
    pub(crate) bvh_first: u32,
    pub(crate) bvh_nodes: u32,
    pub(crate) pad: u32,
}

/// The integrator's light sampler, which the GPU mirrors.
pub(crate) fn light_sampler(scene: &Scene) -> std::borrow::Cow<'_, LightSampler> {
    use std::borrow::Cow;
    match &scene.integrator {
        IntegratorKind::Direct(d) => Cow::Borrowed(&d.lights),
        IntegratorKind::VisOpt(v) => Cow::Borrowed(&v.lights),
        // `ament` marches to every light and picks none, transmittance
        // through surfaces (the scatter kernel) picks no light: any sampler
        // does, its bindings still hold the scene's.
        IntegratorKind::Ament(_) | IntegratorKind::Transmittance { .. } => {
            Cow::Owned(LightSampler::new(
                &scene.world.lights,
                scene.world.radius(),
                scene.world.light_selection,
            ))
        }
        IntegratorKind::VolPath(v) => Cow::Borrowed(&v.lights),
        IntegratorKind::PointMis(p) => Cow::Borrowed(&p.lights),
        IntegratorKind::Restir(r) => Cow::Borrowed(&r.lights),
    }
}

/// light_bvh.wgsl's pipeline constant `LIGHT_BVH`: whether the scene's
/// emitting triangles are picked through a light BVH (without one the
/// driver compiles the descent out).
pub(crate) fn has_light_bvh(scene: &Scene) -> bool {
    light_sampler(scene).bvh().is_some()
}

pub struct LightBuffers {
    pub bind_group_layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
}

fn v4(v: glam::Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

impl LightBuffers {
    /// `properties`: per medium, [`crate::scene_buffers::SceneBuffers::properties`].
    pub fn upload(
        gpu: &Gpu,
        scene: &Scene,
        properties: &[[u32; 5]],
    ) -> Result<LightBuffers, GpuError> {
        let sampler = &*light_sampler(scene);
        let cdf = sampler.cdf(Vertex::Medium);
        // A light's CDF entry and pmf for points of kind `at`.
        let pick = |i: usize, at| {
            let c = sampler.cdf(at).get(i).copied().unwrap_or(1.0);
            [c, sampler.cdf_pmf(i, at)]
        };
        let mut env = EnvParams {
            to_local: [
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
            ],
            width: 1,
            height: 1,
            light_count: scene.lights.len() as u32,
            integral: 0.0,
            pickable: (!cdf.is_empty()) as u32,
            props_ext: scene.media.len() as u32,
            props_blackbody: 4 * scene.media.len() as u32,
            environments: scene
                .lights
                .iter()
                .rposition(|l| l.is_environment())
                .map_or(0, |i| i as u32 + 1),
            bilinear: 0,
            bvh_first: scene.lights.len() as u32,
            bvh_nodes: 0,
            pad: 0,
        };
        let (mut env_rgb, mut env_cdf) = (vec![[0.0f32; 4]], vec![0.0f32, 1.0, 0.0, 1.0]);
        let mut records = Vec::new();
        let mut envmaps = 0;
        for (i, l) in scene.lights.iter().enumerate() {
            let [c, pmf] = pick(i, Vertex::Medium);
            let surface = pick(i, Vertex::Surface);
            let zero = [0.0; 4];
            let trail = (sampler.bvh())
                .filter(|b| b.holds(i))
                .map_or(0, |b| b.trails[i - b.first]);
            let rec = |kind, a, b, c4, d: [f32; 2]| LightGpu {
                kind,
                trail,
                surface,
                a,
                b,
                c: c4,
                d: [d[0], d[1], c, pmf],
                e: zero,
            };
            let kind = || crate::contract::light_id(l);
            // A flat emitter (triangle, disk): origin and area, its two
            // edges or half-axes a, b, the emitting side n relative to a × b.
            let flat = |o, a: glam::Vec3, b: glam::Vec3, n: glam::Vec3, area, radiance| LightGpu {
                e: v4(b, 0.0),
                ..rec(
                    kind(),
                    v4(o, area),
                    v4(radiance, 0.0),
                    v4(a, n.dot(a.cross(b)).signum()),
                    [0.0; 2],
                )
            };
            records.push(match l {
                Light::Constant { radiance } => {
                    rec(kind(), zero, v4(*radiance, 0.0), zero, [0.0; 2])
                }
                Light::Envmap(e) => {
                    envmaps += 1;
                    if envmaps > 1 {
                        return Err(GpuError(format!(
                            "lights.{i}: the GPU backend takes one environment map per scene"
                        )));
                    }
                    let (rgb, cdfs, to_local, integral) = e.gpu_layout();
                    env.width = e.width() as u32;
                    env.height = e.height() as u32;
                    env.integral = integral;
                    env.bilinear = e.is_bilinear() as u32;
                    env.to_local = [
                        v4(to_local.row(0), 0.0),
                        v4(to_local.row(1), 0.0),
                        v4(to_local.row(2), 0.0),
                    ];
                    env_rgb = rgb;
                    env_cdf = cdfs;
                    rec(kind(), zero, zero, zero, [0.0; 2])
                }
                Light::Point {
                    position,
                    intensity,
                } => rec(
                    kind(),
                    v4(*position, 1.0),
                    v4(*intensity, 0.0),
                    zero,
                    [0.0; 2],
                ),
                Light::Directional {
                    direction,
                    irradiance,
                } => rec(
                    kind(),
                    v4(*direction, 0.0),
                    v4(*irradiance, 0.0),
                    zero,
                    [0.0; 2],
                ),
                Light::Spot {
                    position,
                    direction,
                    intensity,
                    cos_falloff_start,
                    cos_total,
                    curve,
                } => rec(
                    kind(),
                    v4(*position, 1.0),
                    v4(*intensity, 0.0),
                    // w: the SpotCurve id.
                    v4(*direction, *curve as u32 as f32),
                    [*cos_falloff_start, *cos_total],
                ),
                Light::Area(t) => flat(t.p0, t.e1, t.e2, t.n, t.area, t.radiance),
                Light::Sphere(l) => rec(
                    kind(),
                    v4(l.centre, l.radius),
                    v4(l.radiance, 0.0),
                    [0.0, 0.0, 0.0, l.inward as u32 as f32],
                    [0.0; 2],
                ),
                // As a triangle: centre, half-axes u and v.
                Light::Disk(l) => flat(l.centre, l.u, l.v, l.n, l.area, l.radiance),
            });
        }
        let mut shading: Vec<[f32; 4]> = scene
            .media
            .iter()
            .map(|m| [m.albedo[0], m.albedo[1], m.albedo[2], m.phase.g])
            .collect();
        // Per medium three vec4s: (albedo grid first + 1, its channels,
        // emission kind, emission grid first + 1) as small exact floats,
        // (radiance, temperature scale), (temperature offset, chromatic
        // channels' first record + 1, 1 when their k varies, 0).
        // Emission kind: 0 none, 1 colour, 2 blackbody.
        let mut ext: Vec<[f32; 4]> = Vec::new();
        for (m, prop) in scene.media.iter().zip(properties) {
            use fogbank_render::world::emission::Emission;
            let kind = crate::contract::emission_id(m.emission.as_ref()) as f32;
            let (radiance, scale, offset) = match &m.emission {
                None => (glam::Vec3::ZERO, 1.0, 0.0),
                Some(Emission::Color { radiance, .. }) => (*radiance, 1.0, 0.0),
                Some(Emission::Blackbody {
                    radiance,
                    scale,
                    offset,
                    ..
                }) => (*radiance, *scale, *offset),
            };
            ext.push([prop[0] as f32, prop[1] as f32, kind, prop[2] as f32]);
            ext.push(v4(radiance, scale));
            ext.push([offset, prop[3] as f32, prop[4] as f32, 0.0]);
        }
        let (bb_min, bb_step, bb) = fogbank_render::world::blackbody::blackbody_table();
        let mut table: Vec<[f32; 4]> = vec![[bb_min, bb_step, bb.len() as f32, 0.0]];
        table.extend(bb.iter().map(|c| v4(*c, 0.0)));
        // One binding for the three (storage bindings per stage are few):
        // the ranges start at `EnvParams::props_ext` and `props_blackbody`.
        shading.extend(ext);
        shading.extend(table);
        if let Some(b) = sampler.bvh() {
            env.bvh_first = b.first as u32;
            env.bvh_nodes = shading.len() as u32;
            shading.extend(light_bvh_nodes(b)?);
        }
        let surfaces = crate::surfaces::SurfaceBuffers::upload(gpu, scene)?;
        let lights_buf = gpu.storage_buffer("lights", bytemuck::cast_slice(&records));
        let env_buf = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("env"),
                contents: bytemuck::bytes_of(&env),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let rgb_buf = gpu.storage_buffer("env_rgb", bytemuck::cast_slice(&env_rgb));
        let cdf_buf = gpu.storage_buffer("env_cdf", bytemuck::cast_slice(&env_cdf));
        let shading_buf = gpu.storage_buffer("shading", bytemuck::cast_slice(&shading));
        let entry = |binding, uniform: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: if uniform {
                    wgpu::BufferBindingType::Uniform
                } else {
                    wgpu::BufferBindingType::Storage { read_only: true }
                },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let bind_group_layout = gpu.bind_group_layout(
            "lights",
            &[
                entry(0, false),
                entry(1, true),
                entry(2, false),
                entry(3, false),
                entry(4, false),
                entry(5, false),
                entry(6, false),
            ],
        );
        let bufs = [
            &lights_buf,
            &env_buf,
            &rgb_buf,
            &cdf_buf,
            &shading_buf,
            &surfaces.nodes,
            &surfaces.data,
        ];
        let bind_group = gpu.bind_group_of("lights", &bind_group_layout, &bufs);
        Ok(LightBuffers {
            bind_group_layout,
            bind_group,
        })
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

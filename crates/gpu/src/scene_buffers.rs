//! One upload per scene: every medium's brick table, constant bricks, voxel
//! data (f16 two per word, or f32) and super-voxel statistics, concatenated
//! into flat storage buffers, with a per-medium record of offsets and
//! placement (`MediumGpu` in `wgsl/medium.wgsl`).

use crate::medium_records::MediumGrids;
use crate::{Gpu, GpuError};
use bytemuck::{Pod, Zeroable};
use fogbank_render::world::emission::Emission;
use fogbank_render::world::field::Field;
use fogbank_render::world::medium::SceneMedium;
use fogbank_render::Scene;
use fogbank_volume::{AnalyticKind, BrickGrid, DensityData, Filter, Medium, Voxel};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MediumGpu {
    pub w2i: [[f32; 4]; 3],
    pub dims: [u32; 3],
    pub filter: u32,
    pub bdims: [u32; 3],
    pub precision: u32,
    pub sv_dims: [u32; 3],
    pub sv_size: f32,
    pub scale: f32,
    pub table_offset: u32,
    pub constants_offset: u32,
    pub data_offset: u32,
    pub sv_offset: u32,
    /// A post-interpolative transfer function's points in the constants
    /// buffer: where they start, (opacity count | colour count << 16) and
    /// the emission count; all 0 without one (see [`pack_transfer`]).
    pub tf_offset: u32,
    pub tf_counts: u32,
    pub tf_emission: u32,
    pub camera_index: [f32; 4],
}

/// The scene's media on the device (bind group 0 of every kernel).
pub struct SceneBuffers {
    /// The scene's media first, then the channels of their property grids
    /// (albedo, emission, temperature), which reuse the grid fetch code.
    pub media: Vec<MediumGpu>,
    /// Per scene medium, where its property grids and chromatic channels
    /// are among `media`.
    pub grids: Vec<MediumGrids>,
    pub bind_group_layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
    /// Bytes uploaded (for stats).
    pub bytes: u64,
    /// Record of the first of the `extra` media of [`SceneBuffers::upload_with`].
    pub extra_first: u32,
    /// Record of the first channel of each of its `fields`.
    pub field_first: Vec<u32>,
}

#[derive(Default)]
struct Packed {
    table: Vec<u32>,
    constants: Vec<f32>,
    data: Vec<u32>,
    supervoxels: Vec<[f32; 4]>,
    /// Grids already packed, by the address of their shared voxel data
    /// (instances of one medium, chromatic channels), with the scale and
    /// offset of their super-voxels: copies are uploaded once, and
    /// super-voxels (in σ_t units) once per scale.
    packed: Vec<(usize, PackedData, f32, u32)>,
}

fn pack_grid<T: Voxel>(
    g: &BrickGrid<T>,
    p: &mut Packed,
    words: impl Fn(&[T]) -> Vec<u32>,
) -> (u32, u32, u32) {
    let (table, constants, data) = g.buffers();
    let offsets = (
        p.table.len() as u32,
        p.constants.len() as u32,
        p.data.len() as u32,
    );
    p.table.extend_from_slice(table);
    p.constants.extend_from_slice(constants);
    p.data.extend(words(data));
    offsets
}

fn check_size(what: &str, len: usize, limit: u64) -> Result<(), GpuError> {
    if (len as u64) * 4 > limit {
        return Err(GpuError(format!(
            "{what}: {} MiB exceed the device's storage-buffer limit of {} MiB",
            (len * 4) >> 20,
            limit >> 20
        )));
    }
    Ok(())
}

impl SceneBuffers {
    pub fn upload(gpu: &Gpu, scene: &Scene) -> Result<SceneBuffers, GpuError> {
        Self::upload_with(gpu, scene, &[], &[])
    }

    /// The scene's media and property grids, then the `extra` media (such
    /// as a medium's mips) as records from [`SceneBuffers::extra_first`] on,
    /// then the channels of `fields` (such as a velocity grid) as property
    /// records ([`SceneBuffers::field_first`]).
    pub fn upload_with(
        gpu: &Gpu,
        scene: &Scene,
        extra: &[&Medium],
        fields: &[&fogbank_render::world::field::Field],
    ) -> Result<SceneBuffers, GpuError> {
        let mut p = Packed::default();
        let mut media = Vec::new();
        for (i, sm) in scene.media.iter().enumerate() {
            let err = |e: GpuError| GpuError(format!("media.{i} ({}): {}", sm.source, e.0));
            let mut record = pack_medium(&sm.medium, scene.camera.origin, &mut p).map_err(err)?;
            pack_transfer(&mut record, &sm.medium, sm.transfer.as_ref(), &mut p).map_err(err)?;
            media.push(record);
        }
        let mut grids = Vec::new();
        for (i, sm) in scene.media.iter().enumerate() {
            grids.push(pack_grids(i, sm, scene.camera.origin, &mut media, &mut p)?);
        }
        let extra_first = media.len() as u32;
        for (i, m) in extra.iter().enumerate() {
            media.push(
                pack_medium(m, scene.camera.origin, &mut p)
                    .map_err(|e| GpuError(format!("derived medium {i}: {}", e.0)))?,
            );
        }
        let mut field_first = Vec::with_capacity(fields.len());
        for f in fields {
            field_first.push(media.len() as u32);
            let (channels, w2i) = f.parts();
            for c in channels {
                media.push(
                    pack_property(c, w2i, &mut p)
                        .map_err(|e| GpuError(format!("{}: {}", f.source, e.0)))?,
                );
            }
        }
        if media.is_empty() {
            // A scene of surfaces alone: one unused record, as the binding
            // must hold one (the kernels loop over `frame.media_count` = 0).
            media.push(MediumGpu::zeroed());
        }
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        check_size("voxel data", p.data.len(), limit)?;
        check_size("brick table", p.table.len(), limit)?;
        check_size("super-voxels", p.supervoxels.len() * 4, limit)?;
        let bufs = [
            gpu.storage_buffer("media", bytemuck::cast_slice(&media)),
            gpu.storage_buffer("brick_table", bytemuck::cast_slice(&p.table)),
            gpu.storage_buffer("brick_constants", bytemuck::cast_slice(&p.constants)),
            gpu.storage_buffer("brick_data", bytemuck::cast_slice(&p.data)),
            gpu.storage_buffer("supervoxels", bytemuck::cast_slice(&p.supervoxels)),
        ];
        let bytes = bufs.iter().map(|b| b.size()).sum();
        let entries: Vec<wgpu::BindGroupLayoutEntry> = (0..bufs.len() as u32)
            .map(|binding| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let bind_group_layout = gpu.bind_group_layout("media", &entries);
        let bind_group = gpu.bind_group_of("media", &bind_group_layout, &bufs.each_ref());
        Ok(SceneBuffers {
            media,
            grids,
            bind_group_layout,
            bind_group,
            bytes,
            extra_first,
            field_first,
        })
    }
}

/// Scene medium `i`'s property grids (albedo, emission or temperature)
/// and chromatic channels as records appended to `media`, and where they
/// are.
fn pack_grids(
    i: usize,
    sm: &SceneMedium,
    camera: glam::Vec3,
    media: &mut Vec<MediumGpu>,
    p: &mut Packed,
) -> Result<MediumGrids, GpuError> {
    let mut push = |f: &Field, media: &mut Vec<MediumGpu>| -> Result<u32, GpuError> {
        let first = media.len() as u32;
        let (channels, w2i) = f.parts();
        for c in channels {
            media.push(
                pack_property(c, w2i, p)
                    .map_err(|e| GpuError(format!("media.{i} ({}): {}", f.source, e.0)))?,
            );
        }
        Ok(first + 1)
    };
    let mut g = MediumGrids::default();
    if let Some(f) = &sm.albedo_grid {
        (g.albedo, g.albedo_channels) = (push(f, media)?, f.channel_count() as u32);
    }
    g.emission = match &sm.emission {
        Some(Emission::Color { grid: Some(f), .. }) => push(f, media)?,
        Some(Emission::Blackbody { temperature, .. }) => push(temperature, media)?,
        _ => 0,
    };
    // Chromatic extinction: each channel's medium (Chroma::channels).
    if let Some(c) = &sm.chroma {
        (g.chroma, g.chroma_varies) = (media.len() as u32 + 1, c.varying() as u32);
        for (k, cm) in c.channels.iter().enumerate() {
            media.push(pack_medium(cm, camera, p).map_err(|e| {
                GpuError(format!("media.{i} ({}) channel {k}: {}", sm.source, e.0))
            })?);
        }
    }
    Ok(g)
}

/// (table, constants, data offsets), storage, dimensions.
type PackedData = ((u32, u32, u32), u32, [u32; 3]);

/// Packs a grid's bricks: (table, constants, data offsets), storage (0 f16,
/// 1 f32) and dimensions; analytic data is refused with `analytic_error`.
fn pack_data(
    data: &DensityData,
    p: &mut Packed,
    analytic_error: &str,
) -> Result<PackedData, GpuError> {
    match data {
        DensityData::F16(g) => Ok((pack_grid(g, p, pack_f16), 0, g.dims())),
        DensityData::F32(g) => Ok((
            pack_grid(g, p, |d| d.iter().map(|v| v.to_bits()).collect()),
            1,
            g.dims(),
        )),
        // A homogeneous medium (Mitsuba's `homogeneous`, a `constvolume`):
        // one constant brick per 8³ voxels, exact under every filter since
        // lookups clamp to the grid.
        DensityData::Analytic(a) => match a.kind {
            AnalyticKind::Constant { value } => {
                let g = BrickGrid::<f32>::from_fn([a.n; 3], |_, _, _| value)
                    .map_err(|e| GpuError(e.to_string()))?;
                Ok((
                    pack_grid(&g, p, |d| d.iter().map(|v| v.to_bits()).collect()),
                    1,
                    g.dims(),
                ))
            }
            _ => Err(GpuError(analytic_error.into())),
        },
    }
}

/// The address of a grid's voxel data (shared by clones), if it has any.
fn data_address(d: &DensityData) -> Option<usize> {
    match d {
        DensityData::F16(g) => Some(g.buffers().0.as_ptr() as usize),
        DensityData::F32(g) => Some(g.buffers().0.as_ptr() as usize),
        DensityData::Analytic(_) => None,
    }
}

fn pack_medium(m: &Medium, camera: glam::Vec3, p: &mut Packed) -> Result<MediumGpu, GpuError> {
    let address = data_address(&m.data);
    // Instances share data, scale and super-voxel statistics; chromatic
    // channels share data only.
    let scale = m.sigma_t_scale;
    let seen = p.packed.iter().find(|e| Some(e.0) == address);
    let same_scale = p
        .packed
        .iter()
        .find(|e| Some(e.0) == address && e.2 == scale)
        .map(|e| e.3);
    let (offsets, precision, dims) = match seen {
        Some(e) => e.1,
        None => pack_data(
            &m.data,
            p,
            "analytic media other than constant are CPU-only; use a voxel grid (cloud, vdb, vol, raw)",
        )?,
    };
    let sv_offset = match same_scale {
        Some(sv) => sv,
        None => {
            let sv_offset = p.supervoxels.len() as u32;
            p.supervoxels.extend(
                m.supervoxels
                    .cells
                    .iter()
                    .map(|c| [c.min, c.max, c.mean, c.importance]),
            );
            if let Some(a) = address {
                p.packed
                    .push((a, (offsets, precision, dims), scale, sv_offset));
            }
            sv_offset
        }
    };
    let a = m.world_to_index;
    let c = a.transform_point3(camera.as_dvec3()).as_vec3();
    Ok(MediumGpu {
        filter: match m.filter {
            Filter::Nearest => 0,
            Filter::Trilinear => 1,
            Filter::StochasticTrilinear => 2,
        },
        sv_dims: m.supervoxels.dims,
        sv_size: m.supervoxels.size as f32,
        scale: m.sigma_t_scale,
        camera_index: [c.x, c.y, c.z, 1.0],
        ..grid_record(a, (offsets, precision, dims), sv_offset)
    })
}

/// The record of a packed grid with index→world `w2i`: trilinear, unscaled,
/// one super-voxel over the whole grid, no transfer function; the density
/// media set their own filter, scale, super-voxels and camera.
fn grid_record(w2i: fogbank_math::DAffine3, packed: PackedData, sv_offset: u32) -> MediumGpu {
    let (offsets, precision, dims) = packed;
    MediumGpu {
        w2i: affine_rows(w2i),
        dims,
        filter: 1,
        bdims: dims.map(|d| d.div_ceil(8)),
        precision,
        sv_dims: [1, 1, 1],
        sv_size: dims.into_iter().max().unwrap_or(1) as f32,
        scale: 1.0,
        table_offset: offsets.0,
        constants_offset: offsets.1,
        data_offset: offsets.2,
        sv_offset,
        tf_offset: 0,
        tf_counts: 0,
        tf_emission: 0,
        camera_index: [0.0; 4],
    }
}

/// Most points a transfer-function curve may have on the device (counts
/// share one word).
const MAX_TF_POINTS: usize = 0xffff;

/// Appends a post-interpolative transfer function to the constants buffer
/// and records it in the medium's record: opacity as (x, α) pairs, then
/// colour and emission as (x, r, g, b) quads, in the grid's stored units
/// (`medium.wgsl` `classify`, `properties.wgsl`).
fn pack_transfer(
    record: &mut MediumGpu,
    m: &Medium,
    lookup: Option<&fogbank_render::world::transfer::TransferLookup>,
    p: &mut Packed,
) -> Result<(), GpuError> {
    let Some(opacity) = &m.opacity else {
        return Ok(());
    };
    let color = lookup.map(|l| &l.color);
    let emission = lookup.and_then(|l| l.emission.as_ref());
    let counts = [
        opacity.len(),
        color.map_or(0, |c| c.len()),
        emission.map_or(0, |e| e.len()),
    ];
    if counts.iter().any(|&n| n > MAX_TF_POINTS) {
        return Err(GpuError(format!(
            "a transfer-function curve has more than {MAX_TF_POINTS} points"
        )));
    }
    record.tf_offset = p.constants.len() as u32;
    record.tf_counts = counts[0] as u32 | (counts[1] as u32) << 16;
    record.tf_emission = counts[2] as u32;
    for (x, [a]) in opacity.points() {
        p.constants.extend([x, a]);
    }
    for curve in color.into_iter().chain(emission) {
        for (x, [r, g, b]) in curve.points() {
            p.constants.extend([x, r, g, b]);
        }
    }
    Ok(())
}

/// A property grid channel as a record of the media buffer: trilinear,
/// unscaled, with one empty super-voxel (never traversed).
fn pack_property(
    data: &DensityData,
    w2i: fogbank_math::DAffine3,
    p: &mut Packed,
) -> Result<MediumGpu, GpuError> {
    let packed = pack_data(
        data,
        p,
        "analytic property grids other than constant are CPU-only; use a voxel grid",
    )?;
    let sv_offset = p.supervoxels.len() as u32;
    p.supervoxels.push([0.0; 4]);
    Ok(grid_record(w2i, packed, sv_offset))
}

fn pack_f16(d: &[half::f16]) -> Vec<u32> {
    d.chunks(2)
        .map(|c| {
            let lo = c[0].to_bits() as u32;
            let hi = c.get(1).map_or(0, |h| h.to_bits() as u32);
            lo | (hi << 16)
        })
        .collect()
}

/// The rows of a 3×4 affine map (world → index) in f32.
fn affine_rows(a: fogbank_math::DAffine3) -> [[f32; 4]; 3] {
    let (x, y, z, t) = (
        a.matrix3.x_axis,
        a.matrix3.y_axis,
        a.matrix3.z_axis,
        a.translation,
    );
    std::array::from_fn(|r| [x[r] as f32, y[r] as f32, z[r] as f32, t[r] as f32])
}

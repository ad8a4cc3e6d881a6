//! Lerzer and Dachsbacher 2025 on the GPU: bind group 3 of the `visopt` and
//! `ament` kernels — their parameters, the medium's
//! importance rules (masks and a pre-classified importance are property
//! records of the media buffer) and visopt's camera lists, built and frozen
//! on the CPU ([`CameraLists`]) and only read on the device.

use crate::context::buffer_entry;
use crate::contract::{
    scattering_id, RULE_BOX, RULE_EXTINCTION, RULE_GRADIENT, RULE_HALF_SPACE, RULE_MASK,
    RULE_SCALAR, VISOPT_JITTER, VISOPT_OPTIMISE, VISOPT_PRE_NEAREST, VISOPT_PRINTED,
    VISOPT_SHADING,
};
use crate::{Gpu, GpuError};
use bytemuck::{Pod, Zeroable};
use fogbank_render::integrators::visopt::lists::CameraLists;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::world::field::Field;
use fogbank_render::world::importance::Importance;
use fogbank_render::Scene;
use wgpu::util::DeviceExt;

/// WGSL `VisOptUniform` (`params.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct VisOptUniform {
    pub p: f32,
    pub q: f32,
    pub r: f32,
    pub lambda: f32,
    pub unit: f32,
    pub n: f32,
    pub step: f32,
    pub merge_distance: f32,
    pub flags: u32,
    pub rule_count: u32,
    pub pre_field: u32,
    pub light_samples: u32,
    pub scattering: u32,
    pub max_depth: u32,
    pub tolerance: f32,
    pub lists_first: u32,
}

/// WGSL `ImportanceRuleGpu`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct ImportanceRuleGpu {
    pub value: f32,
    pub flags: u32,
    pub mask: u32,
    pub mask_threshold: f32,
    pub ranges: [f32; 4],
    pub gradient: [f32; 4],
    pub box_lo: [f32; 4],
    pub box_hi: [f32; 4],
    pub half_space: [f32; 4],
}

/// The fields the rules of the scene's one medium read on the device, in
/// the order [`VisOptBuffers::build`] expects them as property records:
/// every rule's mask, then a pre-classified importance.
pub(crate) fn importance_fields(scene: &Scene) -> Vec<&Field> {
    let Some(sm) = scene.media.first() else {
        return Vec::new();
    };
    let imp = &sm.importance;
    let mut fields: Vec<&Field> = imp
        .rules
        .iter()
        .filter_map(|r| r.mask.as_ref().map(|(f, _)| f))
        .collect();
    fields.extend(imp.pre.as_ref().map(|p| p.parts().0));
    fields
}

/// The rules as records; `first` holds the first property record of each
/// field of [`importance_fields`].
fn pack_rules(imp: &Importance, first: &[u32]) -> Vec<ImportanceRuleGpu> {
    let mut masks = first.iter();
    imp.rules
        .iter()
        .map(|r| {
            let mut g = ImportanceRuleGpu {
                value: r.value,
                ..Default::default()
            };
            let mut set = |bit: u32| g.flags |= bit;
            if let Some([lo, hi]) = r.extinction {
                set(RULE_EXTINCTION);
                g.ranges[..2].copy_from_slice(&[lo, hi]);
            }
            if let Some([lo, hi]) = r.scalar {
                set(RULE_SCALAR);
                g.ranges[2..].copy_from_slice(&[lo, hi]);
            }
            if let Some([lo, hi]) = r.gradient {
                set(RULE_GRADIENT);
                g.gradient[..2].copy_from_slice(&[lo, hi]);
            }
            if let Some([lo, hi]) = r.region {
                set(RULE_BOX);
                g.box_lo = lo.extend(0.0).into();
                g.box_hi = hi.extend(0.0).into();
            }
            if let Some((n, c)) = r.half_space {
                set(RULE_HALF_SPACE);
                g.half_space = n.extend(c).into();
            }
            if let Some((_, threshold)) = &r.mask {
                set(RULE_MASK);
                g.mask = *masks.next().expect("one record per mask");
                g.mask_threshold = *threshold;
            }
            g
        })
        .collect()
}

/// Group 3 of the `visopt` and `ament` kernels.
pub(crate) struct VisOptBuffers {
    pub(crate) layout: wgpu::BindGroupLayout,
    pub(crate) bind_group: wgpu::BindGroup,
    /// Bytes of the camera lists and the NEE-list scratch (Table 3's memory).
    pub(crate) bytes: u64,
    /// Rows per dispatch: the scratch holds one NEE list per pixel of a
    /// band of this many rows (a multiple of 8, the workgroup height).
    pub(crate) band_rows: u32,
}

/// (rows per band, bytes) of the NEE-list scratch `visopt` allocates at
/// `width`×`height` with `light_samples` entries per list: bands fit
/// [`Gpu::scratch_budget`] and the device's storage-buffer limit.
pub fn scratch(gpu: &Gpu, width: u32, height: u32, light_samples: u32) -> (u32, u64) {
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let rows = band_rows(width, height, light_samples, gpu.scratch_budget.min(limit));
    let bytes = width as u64 * rows as u64 * light_samples as u64 * 16;
    (rows, bytes.max(16))
}

/// Rows per band so that `width` × rows lists of `entries` fit `budget`
/// bytes: a multiple of 8, at least 8, at most the image (rounded up).
fn band_rows(width: u32, height: u32, entries: u32, budget: u64) -> u32 {
    if entries == 0 {
        return height.div_ceil(8) * 8;
    }
    let per_row = width as u64 * entries as u64 * 16;
    let rows = (budget / per_row.max(1)).max(8) as u32 / 8 * 8;
    rows.min(height.div_ceil(8) * 8)
}

/// The integrator's parameters in the uniform, and its camera lists when
/// it optimises with them (`visopt`; `ament` marches without).
fn integrator_uniform<'s>(
    scene: &'s Scene,
    u: &mut VisOptUniform,
) -> Result<Option<&'s CameraLists>, GpuError> {
    let flag = |bit: u32, on: bool| if on { bit } else { 0 };
    Ok(match &scene.integrator {
        IntegratorKind::VisOpt(v) => {
            let p = &v.params;
            (u.p, u.q, u.r, u.lambda, u.n) = (p.p, p.q, p.r, p.lambda, p.n);
            u.unit = v.unit;
            u.merge_distance = p.merge_distance;
            u.light_samples = p.light_samples;
            u.scattering = scattering_id(p.scattering);
            u.max_depth = p.max_depth;
            u.flags |= flag(VISOPT_OPTIMISE, p.optimise) | flag(VISOPT_SHADING, p.shading);
            p.optimise.then(|| v.lists(&scene.world))
        }
        IntegratorKind::Ament(a) => {
            let p = &a.params;
            (u.p, u.q, u.r, u.lambda, u.n) = (p.p, p.q, p.r, p.lambda, p.n);
            u.unit = a.unit;
            u.step = p.step;
            u.flags |= flag(VISOPT_OPTIMISE, p.optimise)
                | flag(VISOPT_SHADING, p.shading)
                | flag(VISOPT_PRINTED, p.printed)
                | flag(VISOPT_JITTER, p.jitter);
            None
        }
        other => {
            return Err(GpuError(format!(
                "integrator \"{}\" has no Lerzer and Dachsbacher 2025 buffers",
                other.name()
            )))
        }
    })
}

/// Group 3 of `visopt` and `ament` over `media` (uploaded with
/// [`importance_fields`]).
pub(crate) fn group3(
    gpu: &Gpu,
    scene: &Scene,
    media: &crate::scene_buffers::SceneBuffers,
) -> Result<Option<crate::integrators::plugin::Group3>, GpuError> {
    let v = VisOptBuffers::build(gpu, scene, &media.field_first)?;
    Ok(Some(crate::integrators::plugin::Group3 {
        layout: v.layout,
        bind_group: v.bind_group,
        bytes: v.bytes,
        band_rows: Some(v.band_rows),
        stream: None,
    }))
}

impl VisOptBuffers {
    /// `field_first`: the property records of [`importance_fields`] as
    /// [`crate::scene_buffers::SceneBuffers::field_first`] gives them.
    pub(crate) fn build(
        gpu: &Gpu,
        scene: &Scene,
        field_first: &[u32],
    ) -> Result<VisOptBuffers, GpuError> {
        let sm = scene.media.first().ok_or_else(|| {
            GpuError("Lerzer and Dachsbacher 2025's integrators need one medium".into())
        })?;
        let imp = &sm.importance;
        let flag = |bit: u32, on: bool| if on { bit } else { 0 };
        let mut u = VisOptUniform {
            rule_count: imp.rules.len() as u32,
            tolerance: imp.tolerance(),
            ..Default::default()
        };
        if let Some(pre) = &imp.pre {
            let masks = field_first.len() - 1;
            u.pre_field = field_first[masks] + 1;
            u.flags |= flag(VISOPT_PRE_NEAREST, pre.parts().1);
        }
        let empty = CameraLists::default();
        let lists = integrator_uniform(scene, &mut u)?.unwrap_or(&empty);
        // The rules (6 words each), then the headers (absolute offsets),
        // then the pool: one buffer.
        let rules = pack_rules(imp, field_first);
        let mut data: Vec<[u32; 4]> = bytemuck::cast_slice(&rules).to_vec();
        u.lists_first = data.len() as u32;
        let first = u.lists_first + lists.pixels.len() as u32;
        data.extend(
            lists
                .pixels
                .iter()
                .map(|&(o, n, kz, len)| [first + o, n, kz.to_bits(), len.to_bits()]),
        );
        data.extend(
            lists
                .pool
                .iter()
                .map(|s| [s.t, s.l, s.k, s.big_k].map(f32::to_bits)),
        );
        let (w, h) = (scene.camera.width, scene.camera.height);
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        let (rows, scratch_bytes) = scratch(gpu, w, h, u.light_samples);
        if scratch_bytes > limit || (data.len() as u64) * 16 > limit {
            return Err(GpuError(format!(
                "visopt: the lists need more than the device's storage-buffer limit of {} MiB \
                 (lower integrator.light_samples or the image width)",
                limit >> 20
            )));
        }
        let device = &gpu.device;
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("visopt params"),
            contents: bytemuck::bytes_of(&u),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let data_buf = gpu.storage_buffer(
            "Lerzer and Dachsbacher 2025 rules and lists",
            bytemuck::cast_slice(&data),
        );
        let scratch = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("visopt NEE-list scratch"),
            size: scratch_bytes,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let layout = gpu.bind_group_layout(
            "visopt",
            &[
                buffer_entry(0, wgpu::BufferBindingType::Uniform),
                buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: true }),
                buffer_entry(2, wgpu::BufferBindingType::Storage { read_only: false }),
            ],
        );
        let bind_group = gpu.bind_group_of("visopt", &layout, &[&uniform, &data_buf, &scratch]);
        Ok(VisOptBuffers {
            layout,
            bind_group,
            bytes: lists.memory_bytes() as u64 + scratch_bytes,
            band_rows: rows,
        })
    }
}

#[cfg(test)]
mod visopt_layout_test {
    use super::*;
    use crate::shaders::check_layout;

    #[test]
    fn bands_fit_the_scratch_budget() {
        // 800 × 200 × 16 B = 2.56 MB per row: 128 MiB hold 52 rows → 48.
        assert_eq!(band_rows(800, 800, 200, 128 << 20), 48);
        assert_eq!(band_rows(800, 30, 200, 128 << 20), 32);
        assert_eq!(band_rows(20, 16, 0, 128 << 20), 16);
        // Very wide images still get one workgroup row.
        assert_eq!(band_rows(100_000, 64, 256, 1 << 20), 8);
    }

    #[test]
    fn records_match_their_wgsl_structs() {
        let src = super::super::source::source();
        let f = |n: &[&'static str], step: usize| -> Vec<(&'static str, usize)> {
            n.iter().enumerate().map(|(i, s)| (*s, i * step)).collect()
        };
        check_layout(
            &src,
            "VisOptUniform",
            std::mem::size_of::<VisOptUniform>(),
            &f(
                &[
                    "p",
                    "q",
                    "r",
                    "lambda",
                    "unit",
                    "n",
                    "step",
                    "merge_distance",
                    "flags",
                    "rule_count",
                    "pre_field",
                    "light_samples",
                    "scattering",
                    "max_depth",
                    "tolerance",
                    "lists_first",
                ],
                4,
            ),
        );
        check_layout(
            &src,
            "ImportanceRuleGpu",
            std::mem::size_of::<ImportanceRuleGpu>(),
            &[
                ("value", 0),
                ("flags", 4),
                ("mask", 8),
                ("mask_threshold", 12),
                ("ranges", 16),
                ("gradient", 32),
                ("box_lo", 48),
                ("box_hi", 64),
                ("half_space", 80),
            ],
        );
    }
}

//! The restir passes' uniform (`RestirUniform` in `wgsl/params.wgsl`):
//! the integrator's parameters, the media records of its mips, and what one
//! frame of one batch of sequences reads and writes.

use bytemuck::{Pod, Zeroable};
use fogbank_render::integrators::restir::{RestirParams, ReuseMis};
use fogbank_render::world::velocity::Velocity;

/// Bytes of one stored reservoir (`Stored` in `wgsl/reservoir.wgsl`).
pub const STORED_BYTES: u64 = 352;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct RestirUniform {
    pub(crate) batch: u32,
    pub(crate) first_sequence: u32,
    pub(crate) frame_index: u32,
    pub(crate) accumulate: u32,
    pub(crate) region_cand: u32,
    pub(crate) region_temporal: u32,
    pub(crate) region_spatial_in: u32,
    pub(crate) region_spatial_out: u32,
    pub(crate) region_prev: u32,
    pub(crate) region_final: u32,
    pub(crate) temporal: u32,
    pub(crate) max_depth: u32,
    pub(crate) candidates: u32,
    pub(crate) mis: u32,
    pub(crate) neighbours: u32,
    pub(crate) radius: f32,
    pub(crate) temporal_cap: f32,
    pub(crate) primary_record: u32,
    pub(crate) indirect_record: u32,
    pub(crate) nee_record: u32,
    pub(crate) reuse_record: u32,
    pub(crate) mip1_record: u32,
    pub(crate) nee_transmittance: u32,
    pub(crate) reuse_step: f32,
    pub(crate) rr_depth: u32,
    pub(crate) vertex_reuse: u32,
    pub(crate) reprojection: u32,
    pub(crate) velocity_resampling: u32,
    pub(crate) pad: [u32; 4],
    /// The current frame's velocity ([`VelocityGpu`]).
    pub(crate) velocity_kind: u32,
    pub(crate) velocity_record: u32,
    pub(crate) frame_dt: f32,
    pub(crate) pad4: u32,
    pub(crate) velocity: [[f32; 4]; 6],
    pub(crate) r2: [[f32; 4]; 16],
}

/// A frame's medium velocity as the GPU evaluates it (`velocity_at` in
/// `wgsl/candidates.wgsl`): `VELOCITY_GRID`: rows 0–2 the linear map
/// of the grid's vectors to world vectors, the grid's channels from record
/// `record`; `VELOCITY_AFFINE`: v(p) = rows 0–2 · (p, 1) where rows 3–5 ·
/// (p, 1) lies in the unit cube, 0 elsewhere.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct VelocityGpu {
    pub(crate) kind: u32,
    pub(crate) record: u32,
    pub(crate) rows: [[f32; 4]; 6],
    /// Seconds since the previous frame.
    pub(crate) dt: f32,
}

impl VelocityGpu {
    /// `v` of a medium, with its grid's first record `record` (if a grid).
    pub(crate) fn new(v: Option<&Velocity>, record: u32, dt: f32) -> VelocityGpu {
        use crate::contract::velocity_id;
        let mut out = VelocityGpu {
            kind: velocity_id(v),
            record,
            rows: [[0.0; 4]; 6],
            dt,
        };
        let row = |m: glam::DMat3, c: glam::DVec3, r: usize| {
            [m.row(r).x, m.row(r).y, m.row(r).z, c[r]].map(|x| x as f32)
        };
        match v {
            None => {}
            Some(Velocity::Constant(c)) => {
                for r in 0..3 {
                    out.rows[r] = row(glam::DMat3::ZERO, c.as_dvec3(), r);
                }
            }
            Some(Velocity::Grid { to_world, .. }) => {
                for r in 0..3 {
                    out.rows[r] = row(to_world.as_dmat3(), glam::DVec3::ZERO, r);
                }
            }
            Some(Velocity::Plume {
                world_to_unit,
                unit_to_world,
            }) => {
                // plume_velocity is affine in the unit-cube position x:
                // A x + b, recovered from four evaluations; in world
                // coordinates v(p) = U (A (W p) + b).
                let f = |x: glam::Vec3| fogbank_volume::plume::plume_velocity(x).as_dvec3();
                let b = f(glam::Vec3::ZERO);
                let a = glam::DMat3::from_cols(
                    f(glam::Vec3::X) - b,
                    f(glam::Vec3::Y) - b,
                    f(glam::Vec3::Z) - b,
                );
                let u = unit_to_world.as_dmat3();
                let m = u * a * world_to_unit.matrix3;
                let c = u * (a * world_to_unit.translation + b);
                for r in 0..3 {
                    out.rows[r] = row(m, c, r);
                    out.rows[3 + r] = row(world_to_unit.matrix3, world_to_unit.translation, r);
                }
            }
        }
        out
    }

    pub(crate) fn apply(&self, u: &mut RestirUniform) {
        u.velocity_kind = self.kind;
        u.velocity_record = self.record;
        u.frame_dt = self.dt;
        u.velocity = self.rows;
    }
}

/// WGSL `MIS_*`: the index in [`ReuseMis::ALL`] (`contract::wgsl_prelude`).
pub(crate) fn mis_id(m: ReuseMis) -> u32 {
    ReuseMis::ALL
        .iter()
        .position(|&x| x == m)
        .expect("every variant") as u32
}

/// Media records of the mips: record of level l ≥ 1 is `first_mip + l − 1`
/// (level 0 is the scene's medium, record 0); `bc4` the record of the
/// compressed reuse mip, when there is one.
pub(crate) struct MipRecords {
    pub(crate) first_mip: u32,
    pub(crate) bc4: Option<u32>,
}

impl MipRecords {
    fn level(&self, l: u32) -> u32 {
        if l == 0 {
            0
        } else {
            self.first_mip + l - 1
        }
    }
}

impl RestirUniform {
    /// The frame-independent part, from the integrator's parameters.
    pub(crate) fn new(p: &RestirParams, mips: &MipRecords, batch: u32) -> RestirUniform {
        use fogbank_render::integrators::restir::neighbours::r2;
        let mut pts = [[0.0f32; 4]; 16];
        for (k, v) in pts.iter_mut().enumerate() {
            let (a, b) = (r2(2 * k as u32), r2(2 * k as u32 + 1));
            *v = [a[0], a[1], b[0], b[1]];
        }
        RestirUniform {
            batch,
            first_sequence: 0,
            frame_index: 0,
            accumulate: 0,
            region_cand: 0,
            region_temporal: 0,
            region_spatial_in: 0,
            region_spatial_out: 0,
            region_prev: 0,
            region_final: 0,
            temporal: 0,
            max_depth: p.max_depth,
            candidates: p.candidates,
            mis: mis_id(p.mis),
            neighbours: p.neighbours,
            radius: p.radius,
            temporal_cap: p.q(),
            primary_record: mips.level(p.primary_mip),
            indirect_record: mips.level(p.indirect_mip),
            nee_record: mips.level(p.nee_mip),
            reuse_record: mips.bc4.unwrap_or(mips.level(p.reuse_mip)),
            mip1_record: mips.level(1),
            nee_transmittance: p.nee_transmittance as u32,
            reuse_step: p.reuse_step,
            rr_depth: p.rr_depth,
            vertex_reuse: p.vertex_reuse as u32,
            reprojection: p.reprojection as u32,
            velocity_resampling: p.velocity_resampling as u32,
            pad: [0; 4],
            velocity_kind: 0,
            velocity_record: 0,
            frame_dt: 0.0,
            pad4: 0,
            velocity: [[0.0; 4]; 6],
            r2: pts,
        }
    }
}

/// Which of the three reservoir regions each pass of a frame reads and
/// writes: candidates into a region the previous frame's reservoirs are
/// not in, temporal reuse into the third, spatial reuse back into a free
/// one; the final region is the next frame's previous one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Regions {
    pub(crate) cand: u32,
    pub(crate) temporal: Option<u32>,
    pub(crate) spatial: Option<(u32, u32)>,
    pub(crate) prev: Option<u32>,
    pub(crate) last: u32,
}

impl Regions {
    pub(crate) fn plan(prev: Option<u32>, temporal: bool, spatial: bool) -> Regions {
        let free: Vec<u32> = (0..3).filter(|r| Some(*r) != prev).collect();
        let (cand, other) = (free[0], free[1]);
        let temporal = (temporal && prev.is_some()).then_some(other);
        let mut last = temporal.unwrap_or(cand);
        let spatial = spatial.then(|| {
            let out = if temporal.is_some() { cand } else { other };
            let io = (last, out);
            last = out;
            io
        });
        Regions {
            cand,
            temporal,
            spatial,
            prev,
            last,
        }
    }

    pub(crate) fn apply(&self, u: &mut RestirUniform) {
        u.region_cand = self.cand;
        u.temporal = self.temporal.is_some() as u32;
        u.region_temporal = self.temporal.unwrap_or(0);
        u.region_prev = self.prev.unwrap_or(0);
        let (si, so) = self.spatial.unwrap_or((0, 0));
        u.region_spatial_in = si;
        u.region_spatial_out = so;
        u.region_final = self.last;
    }
}

#[cfg(test)]
mod regions_test {
    use super::Regions;

    /// No pass reads a region another pass of the frame is writing, and
    /// the previous frame's reservoirs survive until temporal reuse.
    #[test]
    fn passes_never_overwrite_what_they_still_read() {
        let mut prev = None;
        for frame in 0..6 {
            for (t, s) in [(true, true), (true, false), (false, true), (false, false)] {
                let r = Regions::plan(prev, t, s);
                if let Some(p) = prev {
                    assert_ne!(r.cand, p);
                    if let Some(tr) = r.temporal {
                        assert!(tr != p && tr != r.cand, "frame {frame}: {r:?}");
                    }
                }
                if let Some((i, o)) = r.spatial {
                    assert_ne!(i, o, "{r:?}");
                    assert_eq!(i, r.temporal.unwrap_or(r.cand));
                    assert_eq!(o, r.last);
                    if r.temporal.is_none() {
                        assert_ne!(Some(o), prev, "{r:?}");
                    }
                }
            }
            prev = Some(Regions::plan(prev, true, true).last);
        }
    }
}

#[cfg(test)]
mod layout_test {
    use super::{RestirUniform, STORED_BYTES};
    use crate::shaders::wgsl_struct;
    use std::mem::{offset_of, size_of};

    /// `RestirUniform` and `Stored` have in WGSL the size and member
    /// offsets the Rust side writes and sizes buffers by.
    #[test]
    fn restir_structs_have_the_rust_layout() {
        let src = super::super::source::source();
        let (span, members) = wgsl_struct(&src, "RestirUniform");
        assert_eq!(span as usize, size_of::<RestirUniform>());
        let rust = |name: &str| -> usize {
            macro_rules! at {
                ($($f:ident),*) => {
                    match name {
                        $(stringify!($f) => offset_of!(RestirUniform, $f),)*
                        "pad0" => offset_of!(RestirUniform, pad),
                        "pad1" => offset_of!(RestirUniform, pad) + 4,
                        "pad2" => offset_of!(RestirUniform, pad) + 8,
                        "pad3" => offset_of!(RestirUniform, pad) + 12,
                        other => panic!("WGSL member {other} has no Rust field"),
                    }
                };
            }
            at!(
                batch,
                first_sequence,
                frame_index,
                accumulate,
                region_cand,
                region_temporal,
                region_spatial_in,
                region_spatial_out,
                region_prev,
                region_final,
                temporal,
                max_depth,
                candidates,
                mis,
                neighbours,
                radius,
                temporal_cap,
                primary_record,
                indirect_record,
                nee_record,
                reuse_record,
                mip1_record,
                nee_transmittance,
                reuse_step,
                rr_depth,
                vertex_reuse,
                reprojection,
                velocity_resampling,
                velocity_kind,
                velocity_record,
                frame_dt,
                pad4,
                velocity,
                r2
            )
        };
        for (name, offset) in &members {
            assert_eq!(*offset as usize, rust(name), "RestirUniform.{name}");
        }
        let (stored, _) = wgsl_struct(&src, "Stored");
        assert_eq!(stored as u64, STORED_BYTES, "Stored");
    }
}

#[cfg(test)]
mod velocity_test {
    use super::VelocityGpu;
    use fogbank_math::{DAffine3, DVec3, Vec3};
    use fogbank_render::world::velocity::Velocity;

    /// rows 0–2 · (p, 1) where rows 3–5 · (p, 1) is in the unit cube.
    fn affine(v: &VelocityGpu, p: Vec3) -> Vec3 {
        let o = [p.x, p.y, p.z, 1.0];
        let dot = |r: [f32; 4]| (0..4).map(|i| r[i] * o[i]).sum::<f32>();
        let u = Vec3::new(dot(v.rows[3]), dot(v.rows[4]), dot(v.rows[5]));
        if u.cmplt(Vec3::ZERO).any() || u.cmpgt(Vec3::ONE).any() {
            return Vec3::ZERO;
        }
        Vec3::new(dot(v.rows[0]), dot(v.rows[1]), dot(v.rows[2]))
    }

    /// The GPU's affine encoding of the plume's velocity (placed, scaled
    /// and turned) and of a constant gives Velocity::at at any point,
    /// inside and outside the plume's box.
    #[test]
    fn affine_rows_reproduce_the_cpu_velocity() {
        let unit_xf = DAffine3::from_scale_rotation_translation(
            DVec3::new(1.5, 2.0, 0.8),
            glam::DQuat::from_rotation_y(0.6),
            DVec3::new(-0.7, -1.0, 0.2),
        );
        let plume = Velocity::Plume {
            world_to_unit: unit_xf.inverse(),
            unit_to_world: unit_xf.matrix3.as_mat3(),
        };
        let constant = Velocity::Constant(Vec3::new(0.3, -1.2, 2.0));
        let mut rng = fogbank_math::Pcg32::new(5, 9);
        let mut inside = 0;
        for v in [&plume, &constant] {
            let g = VelocityGpu::new(Some(v), 0, 0.04);
            for _ in 0..2000 {
                // Around the plume's box: unit coordinates in [−¼, 1¼]³.
                let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 1.5
                    - Vec3::splat(0.25);
                let p = unit_xf.transform_point3(u.as_dvec3()).as_vec3();
                let (cpu, gpu) = (v.at(p), affine(&g, p));
                inside += (cpu != Vec3::ZERO) as u32;
                assert!(
                    (cpu - gpu).length() <= 1e-4 * (1.0 + cpu.length()),
                    "{p}: {cpu} vs {gpu}"
                );
            }
        }
        // (1/1.5)³ ≈ 30 % of the points fall inside the plume's box.
        assert!(
            inside > 2000 + 400,
            "points inside the plume's box: {}",
            inside - 2000
        );
    }
}

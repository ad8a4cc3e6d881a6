//! What ReSTIR reads of the scene's medium (Lin et al. 2021 §4.1, §5.1): the
//! full-resolution trilinear σ_t that the integrand F uses, conservative
//! piecewise-constant mips for candidate tracking, and the three kinds of
//! segment transmittance: T* (regular tracking's closed-form pdf), T̃
//! (deterministic ray marching of a mip, inside p̂) and T (exact or an
//! unbiased estimator, in F).

use super::primary::PrimaryT;
use crate::error::SceneError;
use fogbank_estimators::distance::{analytic_trilinear, regular_tracking, TrackedFlight};
use fogbank_estimators::{analytic_trilinear as exact, deterministic_marching, Estimator};
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{Medium, MediumView};
use std::sync::Arc;

/// Highest mip level a parameter may name (levels 1..=3 are the paper's).
pub const MAX_MIP: u32 = 3;

/// Mips 1..=[`MAX_MIP`] of the scene's medium (built once, shared by clones).
#[derive(Clone, Debug)]
pub struct Mips {
    levels: Arc<Vec<Medium>>,
    /// The reuse target's mip through BC4 compression (§5.1), when asked.
    reuse_bc4: Option<Arc<Medium>>,
}

impl Mips {
    /// Super-voxels of 8 mip voxels, as the paper's baseline uses for its
    /// majorants (the mips are walked voxel by voxel, so they only matter
    /// to other tools reading the mip).
    /// With `bc4 = Some(level)`, also mip `level` through BC4 compression.
    pub fn build(m: &Medium, bc4: Option<u32>) -> Result<Mips, SceneError> {
        let err = |e| SceneError(format!("restir: building the medium's mips: {e}"));
        let levels = (1..=MAX_MIP)
            .map(|l| m.mip(l, 8))
            .collect::<Result<Vec<_>, _>>()
            .map_err(err)?;
        let mut mips = Mips {
            levels: Arc::new(levels),
            reuse_bc4: None,
        };
        if let Some(l) = bc4 {
            mips.reuse_bc4 = Some(Arc::new(mips.level(m, l).bc4(8).map_err(err)?));
        }
        Ok(mips)
    }

    /// The medium the reuse target marches: mip `level`, or its BC4 copy.
    pub fn reuse<'a>(&'a self, full: &'a Medium, level: u32) -> &'a Medium {
        match &self.reuse_bc4 {
            Some(b) => b,
            None => self.level(full, level),
        }
    }

    /// Level `l` of `full` (0: `full` itself).
    pub fn level<'a>(&'a self, full: &'a Medium, l: u32) -> &'a Medium {
        match l {
            0 => full,
            l => &self.levels[(l - 1) as usize],
        }
    }
}

/// σ_t at world point `p`: the trilinear field of `m` (0 outside its box),
/// whatever the medium's own filter (stochastic trilinear has this mean).
#[inline]
pub fn sigma_t(m: &Medium, p: Vec3) -> f32 {
    let q = m.world_to_index.transform_point3(p.as_dvec3()).as_vec3();
    let d = m.dims();
    let inside = q.x >= 0.0
        && q.y >= 0.0
        && q.z >= 0.0
        && q.x <= d[0] as f32
        && q.y <= d[1] as f32
        && q.z <= d[2] as f32;
    if !inside {
        return 0.0;
    }
    let v = match m.view() {
        MediumView::F16(v) => v.grid.trilinear(q),
        MediumView::F32(v) => v.grid.trilinear(q),
        MediumView::Analytic(a) => a.field.density(q / a.field.n as f32),
    };
    m.sigma_t_scale * v.max(0.0)
}

/// Free flight along the world `ray` (unit direction) up to `t_max` with
/// a closed-form density (Lin et al. 2021 Eq. 27–28): regular tracking through the
/// nearest-filtered mip `mip` (≥ 1), or exact trilinear free flight at full
/// resolution (`mip` = `full`). Without a collision, `tau` is the optical
/// depth of the whole range (the walk passes with probability exp(−tau)).
pub fn track(
    mip: &Medium,
    full_res: bool,
    ray: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> TrackedFlight {
    let Some((r, t0, t1)) = mip.to_index(ray, 0.0, t_max) else {
        rng.next_f32(); // the same stream whether or not the box is hit
        return TrackedFlight {
            t: None,
            sigma_t: 0.0,
            tau: 0.0,
            lookups: 0,
        };
    };
    match (mip.view(), full_res) {
        (MediumView::F16(v), true) => {
            analytic_trilinear::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::F32(v), true) => {
            analytic_trilinear::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::F16(v), false) => {
            regular_tracking::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::F32(v), false) => {
            regular_tracking::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::Analytic(_), _) => unreachable!("restir refuses analytic media"),
    }
}

/// σ_t* of the mip at world point `p` (nearest lookup), as `track` saw it.
#[inline]
pub fn sigma_t_nearest(mip: &Medium, p: Vec3) -> f32 {
    let q = mip.world_to_index.transform_point3(p.as_dvec3()).as_vec3();
    let v = match mip.view() {
        MediumView::F16(v) => v.grid.nearest(q),
        MediumView::F32(v) => v.grid.nearest(q),
        MediumView::Analytic(a) => a.field.density(q / a.field.n as f32),
    };
    mip.sigma_t_scale * v
}

/// How a path's segments are attenuated when it is evaluated.
pub enum SegmentT<'a> {
    /// T̃ = exp(−τ̃): deterministic midpoint marching of the trilinear field
    /// of `medium` (a mip, or the full grid), `step` of its voxel diagonals
    /// (Lin et al. 2021 §4.3, §5.1). Inside p̂.
    /// `primary`: the frame's primary-ray tables and the pixel whose
    /// centre ray is the path's first segment ([`SegmentT::eval_primary`]).
    Marched {
        medium: &'a Medium,
        step: f32,
        primary: Option<(&'a PrimaryT, usize)>,
    },
    /// The exact T of the full-resolution trilinear field (analytic
    /// piecewise-trilinear integration, Szirmay-Kalos 2011). In F.
    Exact,
    /// An unbiased estimate of T with one of fogbank's estimators. In F.
    Estimated {
        estimator: Estimator,
        rng: &'a mut Pcg32,
    },
}

impl SegmentT<'_> {
    /// [`SegmentT::eval`] of a path's first segment, `[0, t_max]` of the
    /// pixel's centre ray `ray`: from the pixel's table when there is one.
    pub fn eval_primary(&mut self, full: &Medium, ray: &Ray, t_max: f32, lookups: &mut u32) -> f32 {
        if let SegmentT::Marched {
            medium,
            primary: Some((table, pixel)),
            ..
        } = self
        {
            return table.transmittance(medium, *pixel, t_max, lookups);
        }
        self.eval(full, ray, t_max, lookups)
    }

    /// Transmittance of `[0, t_max]` along the world `ray` through `full`
    /// (the scene's medium at full resolution).
    pub fn eval(&mut self, full: &Medium, ray: &Ray, t_max: f32, lookups: &mut u32) -> f32 {
        match self {
            SegmentT::Marched { medium, step, .. } => {
                let Some((r, t0, t1)) = medium.to_index(ray, 0.0, t_max) else {
                    return 1.0;
                };
                let (tau, n) = match medium.view() {
                    MediumView::F16(v) => deterministic_marching::optical_depth(
                        &v,
                        &RaySegment::new(r, t0, t1),
                        *step * SQRT3,
                    ),
                    MediumView::F32(v) => deterministic_marching::optical_depth(
                        &v,
                        &RaySegment::new(r, t0, t1),
                        *step * SQRT3,
                    ),
                    MediumView::Analytic(_) => unreachable!("restir refuses analytic media"),
                };
                *lookups += n;
                (-tau).exp() as f32
            }
            SegmentT::Exact => {
                let Some((r, t0, t1)) = full.to_index(ray, 0.0, t_max) else {
                    return 1.0;
                };
                let (tau, n) = match full.view() {
                    MediumView::F16(v) => exact::optical_depth(&v, &RaySegment::new(r, t0, t1)),
                    MediumView::F32(v) => exact::optical_depth(&v, &RaySegment::new(r, t0, t1)),
                    MediumView::Analytic(_) => unreachable!("restir refuses analytic media"),
                };
                *lookups += n;
                (-tau).exp() as f32
            }
            SegmentT::Estimated { estimator, rng } => {
                let e = fogbank_estimators::transmittance(*estimator, full, ray, t_max, rng);
                *lookups += e.lookups;
                e.transmittance
            }
        }
    }
}

const SQRT3: f32 = 1.732_050_8;

#[cfg(test)]
mod primary_table_test {
    use super::super::primary::PrimaryT;
    use super::SegmentT;
    use crate::world::camera::Camera;
    use fogbank_math::{Pcg32, Vec3};
    use fogbank_volume::medium::unit_box_transform;
    use fogbank_volume::{BrickGrid, DensityData, Filter, Medium, Precision};

    /// The table answers every segment [0, t] of a pixel's centre ray —
    /// before the volume, inside it, on step boundaries, past its exit —
    /// with the marched T̃, bit for bit (so p̂ does not change with it).
    #[test]
    fn table_gives_the_marched_transmittance_bit_for_bit() {
        let grid = BrickGrid::from_fn([19, 23, 17], |i, j, k| {
            ((i * 7 + j * 13 + k * 5) % 11) as f32 / 10.0
        })
        .unwrap();
        let m = Medium::new(
            DensityData::from_f32(grid, Precision::F16),
            6.0,
            Filter::StochasticTrilinear,
            unit_box_transform([19, 23, 17]),
            8,
        );
        let cam = Camera::new(
            Vec3::new(0.3, 0.2, 1.7),
            Vec3::ZERO,
            Vec3::Y,
            40.0,
            true,
            24,
            18,
        )
        .unwrap();
        let mut rng = Pcg32::new(11, 3);
        for step in [1.0f32, 0.37] {
            let table = PrimaryT::build(&m, step, &cam).unwrap();
            let (mut seen, mut inside) = (0, 0);
            for pixel in 0..(24 * 18) {
                let (x, y) = ((pixel % 24) as f32 + 0.5, (pixel / 24) as f32 + 0.5);
                let ray = cam.ray(x, y);
                let mut ts: Vec<f32> = (0..24).map(|_| 3.0 * rng.next_f32()).collect();
                ts.extend([0.0, f32::INFINITY, 1e-7]);
                let starts = table.step_starts(pixel);
                inside += !starts.is_empty() as u32;
                // Step boundaries and just around them.
                for t in starts {
                    ts.extend([t, t.next_up(), t.next_down()]);
                }
                for t in ts {
                    let (mut l1, mut l2) = (0, 0);
                    let marched = SegmentT::Marched {
                        medium: &m,
                        step,
                        primary: None,
                    }
                    .eval(&m, &ray, t, &mut l1);
                    let tabled = table.transmittance(&m, pixel, t, &mut l2);
                    assert_eq!(
                        marched.to_bits(),
                        tabled.to_bits(),
                        "pixel {pixel}, t {t}: {marched} vs {tabled}"
                    );
                    seen += 1;
                }
            }
            assert!(
                inside > 100 && seen > 10_000,
                "{inside} pixels see the volume"
            );
        }
    }
}

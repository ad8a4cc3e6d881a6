//! The reuse target's T̃ along pixels' primary rays, tabulated once per
//! frame (a CPU speed-up; seed 002 §4.3, §5.1). Every p̂ a pixel evaluates —
//! its own candidates' re-targeting, the temporal and spatial Talbot sums
//! over other pixels' paths — marches T̃ from the camera along that pixel's
//! fixed primary ray to the path's first vertex. The march is the same grid
//! of steps from the ray's entry into the volume whatever the end, so one
//! table of running sums per pixel answers every such segment with one
//! trilinear lookup (the cut last step) instead of a march. A query returns
//! exactly what [`deterministic_marching::optical_depth`] returns for the
//! segment — the same partial sums in the same order and the same last
//! step — so p̂ is unchanged bit for bit (tested), and where rounding could
//! make a step end differ it marches instead.

use crate::world::camera::Camera;
use fogbank_estimators::deterministic_marching;
use fogbank_math::{Ray, Vec3};
use fogbank_volume::{Filter, GridView, Medium, MediumView, Voxel};
use rayon::prelude::*;

/// A pixel's march: the index-space ray, its range in the volume, the step
/// in ray parameter and where its running sums start in the table.
#[derive(Clone, Copy, Debug)]
struct Span {
    ray: Ray,
    t0: f32,
    t1: f32,
    dt: f64,
    first: usize,
    steps: usize,
}

/// T̃ tables of every pixel's primary ray through the reuse medium.
#[derive(Debug, Default)]
pub struct PrimaryT {
    spans: Vec<Option<Span>>,
    /// Per pixel, `steps + 1` running sums of the unscaled optical depth.
    sums: Vec<f64>,
    scale: f64,
    /// The march's step in index-space units (voxels).
    step: f32,
}

/// Most running sums kept (8 bytes each); a larger image marches instead.
const MAX_SUMS: usize = 1 << 26;

/// The march of `world` (a pixel's centre ray) through `medium` in steps
/// of `step` voxels, as deterministic_marching::optical_depth walks it over
/// the whole ray: its span and `steps + 1` running sums.
fn march(medium: &Medium, step: f32, world: &Ray) -> (Option<Span>, Vec<f64>) {
    let Some((r, t0, t1)) = medium.to_index(world, 0.0, f32::INFINITY) else {
        return (None, Vec::new());
    };
    let speed = r.d.length() as f64;
    if !(step > 0.0 && speed > 0.0) {
        return (None, Vec::new());
    }
    let dt = step as f64 / speed;
    let (a, b) = (t0 as f64, t1 as f64);
    let steps = ((b - a) / dt).ceil().max(1.0) as usize;
    let mut sums = Vec::with_capacity(steps + 1);
    let mut tau = 0.0f64;
    sums.push(tau);
    for i in 0..steps {
        let lo = a + i as f64 * dt;
        let hi = (lo + dt).min(b);
        tau += match medium.view() {
            MediumView::F16(v) => value(&v, &r, lo, hi),
            MediumView::F32(v) => value(&v, &r, lo, hi),
            MediumView::Analytic(_) => unreachable!("restir refuses analytic media"),
        };
        sums.push(tau);
    }
    let span = Span {
        ray: r,
        t0,
        t1,
        dt,
        first: 0,
        steps,
    };
    (Some(span), sums)
}

fn value<T: Voxel>(v: &GridView<'_, T>, r: &Ray, lo: f64, hi: f64) -> f64 {
    let p = r.at((0.5 * (lo + hi)) as f32);
    v.grid.filtered(Filter::Trilinear, p, Vec3::ZERO) as f64 * (hi - lo)
}

impl PrimaryT {
    /// The tables of `camera`'s pixel-centre rays through `medium` (the
    /// reuse mip) with steps of `step` voxel diagonals; `None` when they
    /// would exceed the memory bound.
    pub fn build(medium: &Medium, step: f32, camera: &Camera) -> Option<PrimaryT> {
        let step = step * SQRT3;
        let (w, h) = (camera.width, camera.height);
        // Rows in parallel: each pixel's span and running sums.
        let rows: Vec<Vec<(Option<Span>, Vec<f64>)>> = (0..h)
            .into_par_iter()
            .map(|y| {
                (0..w)
                    .map(|x| march(medium, step, &camera.ray(x as f32 + 0.5, y as f32 + 0.5)))
                    .collect()
            })
            .collect();
        let total: usize = rows.iter().flatten().map(|(_, s)| s.len()).sum();
        if total > MAX_SUMS {
            return None;
        }
        let mut out = PrimaryT {
            spans: Vec::with_capacity((w * h) as usize),
            sums: Vec::with_capacity(total),
            scale: medium.sigma_t_scale as f64,
            step,
        };
        for (span, sums) in rows.into_iter().flatten() {
            out.spans.push(span.map(|s| Span {
                first: out.sums.len(),
                ..s
            }));
            out.sums.extend(sums);
        }
        Some(out)
    }

    /// T̃ of `[0, t_max]` along the primary ray of `pixel` through `medium`
    /// (the medium the tables were built from): what marching the segment
    /// gives ([`super::volume::SegmentT::Marched`]), bit for bit.
    pub fn transmittance(
        &self,
        medium: &Medium,
        pixel: usize,
        t_max: f32,
        lookups: &mut u32,
    ) -> f32 {
        let Some(Some(s)) = self.spans.get(pixel) else {
            return 1.0;
        };
        // Medium::to_index(ray, 0, t_max): the same entry, the exit cut at t_max.
        let t1 = s.t1.min(t_max);
        if t1.is_nan() || t1 <= s.t0 {
            return 1.0;
        }
        let (a, b) = (s.t0 as f64, t1 as f64);
        let n = ((b - a) / s.dt).ceil().max(1.0) as usize;
        let last_lo = a + (n - 1) as f64 * s.dt;
        // The table's steps before the last end where the march's do unless
        // rounding put the end of step n − 2 past b.
        let exact = n <= s.steps && (n < 2 || a + (n - 2) as f64 * s.dt + s.dt <= b);
        let tau = if exact {
            *lookups += 1;
            let hi = (last_lo + s.dt).min(b);
            let last = match medium.view() {
                MediumView::F16(v) => value(&v, &s.ray, last_lo, hi),
                MediumView::F32(v) => value(&v, &s.ray, last_lo, hi),
                MediumView::Analytic(_) => unreachable!("restir refuses analytic media"),
            };
            (self.sums[s.first + n - 1] + last) * self.scale
        } else {
            let (tau, k) = match medium.view() {
                MediumView::F16(v) => {
                    deterministic_marching::optical_depth(&v, &s.ray, s.t0, t1, self.step)
                }
                MediumView::F32(v) => {
                    deterministic_marching::optical_depth(&v, &s.ray, s.t0, t1, self.step)
                }
                MediumView::Analytic(_) => unreachable!("restir refuses analytic media"),
            };
            *lookups += k;
            tau
        };
        (-tau).exp() as f32
    }
}

const SQRT3: f32 = 1.732_050_8;

#[cfg(test)]
mod primary_test {
    use super::PrimaryT;
    use crate::integrators::restir::volume::SegmentT;
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
                if let Some(Some(s)) = table.spans.get(pixel) {
                    inside += 1;
                    // Step boundaries and just around them.
                    for i in 0..s.steps {
                        let t = (s.t0 as f64 + i as f64 * s.dt) as f32;
                        ts.extend([t, t.next_up(), t.next_down()]);
                    }
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

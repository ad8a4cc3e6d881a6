//! The reuse target's T̃ along pixels' primary rays, tabulated once per
//! frame (a CPU speed-up; Lin et al. 2021 §4.3, §5.1). Every p̂ a pixel evaluates —
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
use fogbank_math::{Ray, RaySegment, Vec3};
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

    /// Where the steps of `pixel`'s march start (ray parameters; empty
    /// when its ray misses the volume): the ends at which a segment's last
    /// step changes, for tests.
    pub fn step_starts(&self, pixel: usize) -> Vec<f32> {
        match self.spans.get(pixel) {
            Some(Some(s)) => (0..s.steps)
                .map(|i| (s.t0 as f64 + i as f64 * s.dt) as f32)
                .collect(),
            _ => Vec::new(),
        }
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
                MediumView::F16(v) => deterministic_marching::optical_depth(
                    &v,
                    &RaySegment::new(s.ray, s.t0, t1),
                    self.step,
                ),
                MediumView::F32(v) => deterministic_marching::optical_depth(
                    &v,
                    &RaySegment::new(s.ray, s.t0, t1),
                    self.step,
                ),
                MediumView::Analytic(_) => unreachable!("restir refuses analytic media"),
            };
            *lookups += k;
            tau
        };
        (-tau).exp() as f32
    }
}

const SQRT3: f32 = 1.732_050_8;

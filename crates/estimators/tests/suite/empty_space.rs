//! Empty-space skipping ([`fogbank_volume::Occupied`]) changes no result:
//! on media with large empty regions, the walks that jump over zero
//! super-voxels agree with plain walks over every voxel — deterministic
//! marching bit for bit, analytic optical depth to rounding, regular
//! tracking and exact trilinear free flight to the same collision (same
//! random number, same τ target).

use crate::support;

use fogbank_estimators::analytic_trilinear::{self, shifted, DualCell};
use fogbank_estimators::deterministic_marching;
use fogbank_estimators::distance::{analytic_trilinear as exact_flight, regular_tracking};
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{BrickGrid, Dda, Filter, GridView, MediumView};
use support::*;

/// Two blobs and a thin sheet in a 40×36×44 box; most super-voxels are
/// exactly zero, and the blobs' faint edges reach into neighbouring ones.
fn sparse() -> BrickGrid<f32> {
    BrickGrid::from_fn([40, 36, 44], |i, j, k| {
        let p = Vec3::new(i as f32, j as f32, k as f32);
        let blob = |c: Vec3, r: f32| (1.0 - (p - c).length() / r).max(0.0);
        let sheet = if k == 30 && i > 20 { 0.3 } else { 0.0 };
        blob(Vec3::new(9.0, 10.0, 12.0), 6.5) + 2.0 * blob(Vec3::new(28.0, 22.0, 18.0), 5.0) + sheet
    })
    .unwrap()
}

fn plain_march(v: &GridView<'_, f32>, r: &Ray, t0: f32, t1: f32, step: f32) -> f64 {
    let dt = step as f64 / r.d.length() as f64;
    let (a, b) = (t0 as f64, t1 as f64);
    let n = ((b - a) / dt).ceil().max(1.0) as u64;
    let mut tau = 0.0f64;
    for i in 0..n {
        let lo = a + i as f64 * dt;
        let hi = (lo + dt).min(b);
        let p = r.at((0.5 * (lo + hi)) as f32);
        tau += v.grid.filtered(Filter::Trilinear, p, Vec3::ZERO) as f64 * (hi - lo);
    }
    tau * v.scale as f64
}

fn plain_exact(v: &GridView<'_, f32>, r: &Ray, t0: f32, t1: f32) -> f64 {
    let (s, n) = shifted(r, v.grid.dims());
    let (o, d) = (s.o.as_dvec3(), s.d.as_dvec3());
    let tau: f64 = Dda::new(&s, 1.0, n, t0, t1)
        .filter(|c| c.t1 > c.t0)
        .map(|c| DualCell::new(v.grid, c.cell).integral(o, d, c.t0 as f64, c.t1 as f64))
        .sum();
    tau * v.scale as f64
}

/// Regular tracking over every voxel: (collision t, τ over the walk).
fn plain_tracking(v: &GridView<'_, f32>, r: &Ray, t0: f32, t1: f32, u: f32) -> (Option<f32>, f64) {
    let target = -(1.0 - u as f64).ln();
    let mut tau = 0.0;
    for s in Dda::new(r, 1.0, v.grid.dims(), t0, t1) {
        let sigma = v.scale as f64 * v.grid.fetch(s.cell[0], s.cell[1], s.cell[2]) as f64;
        let d = sigma * (s.t1 - s.t0) as f64;
        if tau + d >= target && sigma > 0.0 {
            let t = s.t0 as f64 + (target - tau) / sigma;
            return (Some((t as f32).clamp(s.t0, s.t1)), target);
        }
        tau += d;
    }
    (None, tau)
}

#[test]
fn skipping_empty_super_voxels_changes_no_result() {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-3);
    let mut checked = [0u32; 4];
    for (filter, sv) in [
        (Filter::StochasticTrilinear, 4),
        (Filter::Nearest, 8),
        (Filter::Trilinear, 3),
    ] {
        let m = grid_medium(sparse(), filter, 3.0, sv);
        let MediumView::F32(v) = m.view() else {
            unreachable!()
        };
        for (n, ray) in test_rays([40, 36, 44], 1500, 21).into_iter().enumerate() {
            let Some((r, t0, t1)) = m.to_index(&ray, 0.0, f32::INFINITY) else {
                continue;
            };
            let step = [1.732, 0.37, 2.9][n % 3];
            let (march, _) =
                deterministic_marching::optical_depth(&v, &RaySegment::new(r, t0, t1), step);
            assert_eq!(
                march.to_bits(),
                plain_march(&v, &r, t0, t1, step).to_bits(),
                "ray {n}"
            );
            let (exact, _) = analytic_trilinear::optical_depth(&v, &RaySegment::new(r, t0, t1));
            let plain = plain_exact(&v, &r, t0, t1);
            assert!(close(exact, plain), "ray {n}: {exact} vs {plain}");
            checked[0] += (plain > 0.0) as u32;

            // Free flights with the same random number as the plain walk.
            let mut rng = Pcg32::new(n as u64, 5);
            let u = rng.clone().next_f32();
            let tracked =
                regular_tracking::sample_tracked(&v, &RaySegment::new(r, t0, t1), &mut rng);
            let (t, tau) = plain_tracking(&v, &r, t0, t1, u);
            assert_eq!(tracked.t.is_some(), t.is_some(), "ray {n}");
            if let (Some(a), Some(b)) = (tracked.t, t) {
                assert!(
                    (a - b).abs() <= 1e-4 * b.abs().max(1.0),
                    "ray {n}: {a} vs {b}"
                );
                checked[1] += 1;
            } else {
                assert!(close(tracked.tau, tau), "ray {n}: {} vs {tau}", tracked.tau);
            }
            let mut rng = Pcg32::new(n as u64, 6);
            let u = rng.clone().next_f32() as f64;
            let flight = exact_flight::sample_tracked(&v, &RaySegment::new(r, t0, t1), &mut rng);
            let target = -(1.0 - u).ln();
            match flight.t {
                // Collides where the plain optical depth reaches the target.
                Some(t) => {
                    let tau_t = plain_exact(&v, &r, t0, t);
                    assert!(
                        (tau_t - target).abs() < 1e-4 * target.max(1.0),
                        "ray {n}: {tau_t} vs {target}"
                    );
                    checked[2] += 1;
                }
                None => {
                    assert!(
                        plain < target * (1.0 + 1e-9),
                        "ray {n}: escaped with τ {plain} ≥ {target}"
                    );
                    checked[3] += 1;
                }
            }
        }
    }
    assert!(checked.iter().all(|&c| c > 300), "{checked:?}");
}

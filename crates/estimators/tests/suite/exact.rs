//! The deterministic references: analytic trilinear against fine quadrature,
//! regular tracking against exact voxel sums.

use crate::support;

use fogbank_estimators::{analytic_trilinear, regular_tracking};
use fogbank_math::{Aabb, Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{BrickGrid, Filter, GridView, SuperVoxelGrid};
use glam::DVec3;
use support::*;

fn random_grid(n: [u32; 3], seed: u64) -> BrickGrid<f32> {
    let mut rng = Pcg32::new(seed, 3);
    let values: Vec<f32> = (0..n.iter().product::<u32>())
        .map(|_| rng.next_f32() * 2.0)
        .collect();
    BrickGrid::from_fn(n, |i, j, k| values[((k * n[1] + j) * n[0] + i) as usize]).unwrap()
}

fn trilinear_f64(g: &BrickGrid<f32>, p: DVec3) -> f64 {
    let q = p - DVec3::splat(0.5);
    let f = q.floor();
    let w = q - f;
    let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
    let mut v = 0.0;
    for c in 0..8 {
        let (di, dj, dk) = (c & 1, (c >> 1) & 1, (c >> 2) & 1);
        let wx = if di == 1 { w.x } else { 1.0 - w.x };
        let wy = if dj == 1 { w.y } else { 1.0 - w.y };
        let wz = if dk == 1 { w.z } else { 1.0 - w.z };
        v += wx * wy * wz * g.fetch(i + di, j + dj, k + dk) as f64;
    }
    v
}

fn quadrature(ray: &Ray, n: [u32; 3], f: impl Fn(DVec3) -> f64) -> f64 {
    let b = Aabb::new(Vec3::ZERO, Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32));
    let Some((a, c)) = b.intersect(ray, 0.0, f32::INFINITY) else {
        return 0.0;
    };
    let m = 100_000;
    let h = (c - a) as f64 / m as f64;
    let (o, d) = (ray.o.as_dvec3(), ray.d.as_dvec3());
    (0..m)
        .map(|i| f(o + (a as f64 + (i as f64 + 0.5) * h) * d))
        .sum::<f64>()
        * h
}

fn clip(ray: &Ray, n: [u32; 3]) -> Option<(f32, f32)> {
    Aabb::new(Vec3::ZERO, Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32)).intersect(
        ray,
        0.0,
        f32::INFINITY,
    )
}

/// `g` at scale 1 with super-voxels `sv`, looked up with `filter`.
fn view<'a>(g: &'a BrickGrid<f32>, sv: &'a SuperVoxelGrid, filter: Filter) -> GridView<'a, f32> {
    GridView {
        grid: g,
        filter,
        scale: 1.0,
        supervoxels: sv,
        opacity: None,
    }
}

#[test]
fn analytic_trilinear_matches_fine_quadrature() {
    let n = [13, 9, 11];
    let g = random_grid(n, 1);
    let sv = SuperVoxelGrid::build(n, 4, 1, |i, j, k| g.fetch(i, j, k));
    let view = view(&g, &sv, Filter::Trilinear);
    let rays = test_rays(n, 1200, 5);
    let mut checked = 0;
    for ray in &rays {
        let Some((t0, t1)) = clip(ray, n) else {
            continue;
        };
        if t1 - t0 < 1e-3 {
            continue;
        }
        let (tau, _) = analytic_trilinear::optical_depth(&view, &RaySegment::new(*ray, t0, t1));
        let q = quadrature(ray, n, |p| trilinear_f64(&g, p));
        assert!(
            (tau - q).abs() <= 1e-5 * q.abs().max(1e-3),
            "ray {ray:?}: analytic {tau}, quadrature {q}"
        );
        checked += 1;
    }
    assert!(checked >= 1000, "only {checked} rays hit the grid");
}

#[test]
fn regular_tracking_matches_exact_voxel_sums() {
    let n = [13, 9, 11];
    let g = random_grid(n, 2);
    let sv = SuperVoxelGrid::build(n, 4, 0, |i, j, k| g.fetch(i, j, k));
    let view = view(&g, &sv, Filter::Nearest);
    // Axis-parallel rays through voxel centres: τ is the plain sum of a row.
    for j in 0..n[1] as i32 {
        for k in 0..n[2] as i32 {
            let ray = Ray::new(Vec3::new(-3.0, j as f32 + 0.5, k as f32 + 0.5), Vec3::X);
            let (t0, t1) = clip(&ray, n).unwrap();
            let (tau, lookups) =
                regular_tracking::optical_depth(&view, &RaySegment::new(ray, t0, t1));
            let sum: f64 = (0..n[0] as i32).map(|i| g.fetch(i, j, k) as f64).sum();
            assert!(
                (tau - sum).abs() < 1e-5 * sum,
                "row ({j},{k}): {tau} vs {sum}"
            );
            assert_eq!(lookups, n[0]);
        }
    }
    // Arbitrary rays: the exact sum of voxel value × chord length, from an
    // independent computation (sorted plane crossings).
    for ray in test_rays(n, 500, 9) {
        let Some((t0, t1)) = clip(&ray, n) else {
            continue;
        };
        let mut ts = vec![t0 as f64, t1 as f64];
        for (a, &na) in n.iter().enumerate() {
            if ray.d[a] != 0.0 {
                for c in 0..=na {
                    let t = (c as f64 - ray.o[a] as f64) / ray.d[a] as f64;
                    if t > t0 as f64 && t < t1 as f64 {
                        ts.push(t);
                    }
                }
            }
        }
        ts.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let (o, d) = (ray.o.as_dvec3(), ray.d.as_dvec3());
        let exact: f64 = ts
            .windows(2)
            .map(|w| {
                let p = o + 0.5 * (w[0] + w[1]) * d;
                g.fetch(p.x.floor() as i32, p.y.floor() as i32, p.z.floor() as i32) as f64
                    * (w[1] - w[0])
            })
            .sum();
        let (tau, _) = regular_tracking::optical_depth(&view, &RaySegment::new(ray, t0, t1));
        assert!(
            (tau - exact).abs() <= 1e-4 * exact.max(1e-2),
            "ray {ray:?}: {tau} vs {exact}"
        );
    }
}

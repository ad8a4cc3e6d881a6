//! The BVHs against brute force: on a mesh of 10⁵ triangles (a tessellated
//! sphere with small random triangles inside and around it, including
//! degenerate and NaN ones), every ray's closest hit — triangle and
//! distance — and its any-hit answer equal those of testing every
//! triangle, through the CPU's wide BVH (`MeshAccel`) and through the
//! GPU's binary one (`MeshAccel::gpu`, traversed on the CPU). CI runs 5000 rays; `cargo test -p fogbank-geometry --release
//! -- --ignored` runs the 10⁵.

use fogbank_geometry::shapes::{quad_grid, uv_sphere};
use fogbank_geometry::{intersect, Bvh, MeshAccel, RayFrame, TriangleMesh, Walk};
use fogbank_math::testdata::probe_ray;
use fogbank_math::{Pcg32, Ray, Vec3};

fn test_mesh() -> TriangleMesh {
    let sphere = uv_sphere(100, |_, _| 1.0); // 40 000 triangles
    let (mut p, mut t) = (sphere.positions, sphere.triangles);
    let mut rng = Pcg32::new(11, 3);
    let v = |rng: &mut Pcg32| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
    while t.len() < 100_000 {
        let c = (v(&mut rng) - 0.5) * 3.0;
        let k = p.len() as u32;
        let s = 0.05;
        p.push(c);
        p.push(c + (v(&mut rng) - 0.5) * s);
        p.push(c + (v(&mut rng) - 0.5) * s);
        t.push([k, k + 1, k + 2]);
        if t.len() % 997 == 0 {
            // Degenerate (collinear) and NaN triangles.
            p.push(c);
            p.push(c + Vec3::X * s);
            p.push(c + 2.0 * Vec3::X * s);
            p.push(Vec3::NAN);
            t.push([k + 3, k + 4, k + 5]);
            t.push([k + 6, k + 1, k + 2]);
        }
    }
    TriangleMesh::new("test", p, t, vec![], vec![]).unwrap()
}

fn brute(mesh: &TriangleMesh, ray: &Ray, t_max: f32) -> Option<(u32, f32)> {
    let f = RayFrame::new(ray);
    let mut best: Option<(u32, f32)> = None;
    for i in 0..mesh.len() {
        let [a, b, c] = mesh.corners(i);
        let lim = best.map_or(t_max, |b| b.1);
        if let Some(h) = intersect(&f, a, b, c, lim) {
            best = Some((i as u32, h.t));
        }
    }
    best
}

/// Rays from around the sphere towards random points inside the mesh's
/// box (a seventh of them axis-parallel, a third with a finite `t_max`).
fn check_range(accel: &MeshAccel, bvh: &Bvh, range: std::ops::Range<usize>) -> usize {
    let mut hits = 0;
    for k in range {
        let (ray, t_max) = probe_ray(&mut Pcg32::new(5, k as u64), k);
        let want = brute(&accel.mesh, &ray, t_max);
        let got = accel.intersect(&ray, t_max).map(|h| (h.primitive, h.hit.t));
        assert_eq!(got, want, "ray {k}: {ray:?}");
        assert_eq!(
            accel.occluded(&ray, t_max),
            want.is_some(),
            "any-hit, ray {k}"
        );
        let (got, occluded) = binary(accel, bvh, &ray, t_max);
        assert_eq!(got, want, "binary BVH, ray {k}: {ray:?}");
        assert_eq!(occluded, want.is_some(), "binary BVH any-hit, ray {k}");
        hits += want.is_some() as usize;
    }
    hits
}

/// The closest hit and any-hit answer through the binary BVH.
fn binary(accel: &MeshAccel, bvh: &Bvh, ray: &Ray, t_max: f32) -> (Option<(u32, f32)>, bool) {
    let f = RayFrame::new(ray);
    let test = |slot: u32, t_max: f32| {
        let [a, b, c] = accel.mesh.corners(bvh.order[slot as usize] as usize);
        intersect(&f, a, b, c, t_max).map(|h| h.t)
    };
    let closest = bvh
        .closest_hit(ray, t_max, test)
        .map(|(slot, t)| (bvh.order[slot as usize], t));
    (closest, bvh.any_hit(ray, t_max, test))
}

fn check(rays: usize) {
    let accel = MeshAccel::new(test_mesh());
    assert!(accel.mesh.len() >= 100_000);
    let bvh = Bvh::new(&accel.primitive_bounds());
    let depth = bvh.depth();
    assert!(depth < 64, "binary depth {depth}");
    assert!(accel.wide.depth() < 16, "wide depth {}", accel.wide.depth());
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let chunk = rays.div_ceil(threads);
    let hits: usize = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|i| {
                let (a, b) = (&accel, &bvh);
                s.spawn(move || check_range(a, b, i * chunk..((i + 1) * chunk).min(rays)))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).sum()
    });
    // Most rays hit something, some miss: the test is not vacuous.
    assert!(hits > rays / 2 && hits < rays, "{hits} hits of {rays}");
}

#[test]
fn closest_and_any_hit_match_brute_force() {
    check(5_000);
}

#[test]
#[ignore = "the issue's full size (10⁵ rays × 10⁵ triangles): 106 s on 2 cores in release"]
fn closest_and_any_hit_match_brute_force_full_size() {
    check(100_000);
}

#[test]
fn empty_and_all_degenerate_meshes_hit_nothing() {
    let empty = MeshAccel::new(TriangleMesh::default());
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert!(empty.intersect(&ray, f32::INFINITY).is_none());
    assert!(!empty.occluded(&ray, f32::INFINITY));
    let nan =
        TriangleMesh::new("nan", vec![Vec3::NAN; 3], vec![[0, 1, 2]], vec![], vec![]).unwrap();
    let a = MeshAccel::new(nan);
    assert_eq!(a.wide.node_count(), 0);
    assert!(Bvh::new(&a.primitive_bounds()).nodes.is_empty());
    assert!(a.intersect(&ray, f32::INFINITY).is_none());
}

/// Axis-parallel rays whose origin lies exactly on a box plane (1/d = ±∞
/// meets a zero distance: 0·∞ = NaN in the slab test) still reach the
/// triangles there, and an infinite ray parallel to an axis skips the boxes
/// it passes beside. A grid of unit quads in z = 0; rays along ±z from the
/// quads' shared edges and corners, in both signs of zero direction.
#[test]
fn axis_parallel_rays_on_box_planes_find_the_edges_they_graze() {
    let mesh = quad_grid(8);
    let accel = MeshAccel::new(mesh.clone());
    let mut checked = 0;
    for i in 0..=16 {
        for j in 0..=16 {
            for (dz, oz) in [(-1.0f32, 2.0f32), (1.0, -2.0)] {
                for zero in [0.0f32, -0.0] {
                    let o = Vec3::new(i as f32 * 0.5, j as f32 * 0.5, oz);
                    let ray = Ray::new(o, Vec3::new(zero, zero, dz));
                    let want = brute(&mesh, &ray, f32::INFINITY);
                    let got = accel.intersect(&ray, f32::INFINITY);
                    assert_eq!(want.is_some(), got.is_some(), "{ray:?}");
                    if let (Some(w), Some(g)) = (want, got) {
                        assert_eq!(w.1, g.hit.t, "{ray:?}");
                        checked += 1;
                    }
                    assert_eq!(want.is_some(), accel.occluded(&ray, f32::INFINITY));
                }
            }
        }
    }
    // Every ray lands on the grid [0, 8]² (edges and corners included).
    assert_eq!(checked, 17 * 17 * 4);
}

/// No ray leaks through a shared edge or vertex, near the origin or far
/// from it: a 64 × 64 grid of unit quads (two triangles each, so every
/// quad has a diagonal shared edge too, and each square a coplanar
/// duplicate shifted by nothing), placed at 0 and at (10⁴, −10⁴, 5·10³),
/// is shot from random points above at its vertices and at the midpoints
/// of its edges and diagonals. Every ray hits, through both hierarchies,
/// at the brute-force distance to within rounding: triangles meeting at
/// the aimed point give it distances an ulp or two apart, and which of them
/// is found first (by brute force or a traversal) decides which is kept.
#[test]
fn rays_at_shared_edges_and_vertices_never_leak() {
    for offset in [Vec3::ZERO, Vec3::new(1.0e4, -1.0e4, 5.0e3)] {
        let grid = quad_grid(64);
        let positions: Vec<Vec3> = grid.positions.iter().map(|&p| p + offset).collect();
        // Every triangle twice: coplanar, overlapping primitives.
        let mut triangles = grid.triangles.clone();
        triangles.extend_from_slice(&grid.triangles);
        let mesh = TriangleMesh::new("grid", positions, triangles, vec![], vec![]).unwrap();
        let accel = MeshAccel::new(mesh.clone());
        let bvh = Bvh::new(&accel.primitive_bounds());
        let mut rng = Pcg32::new(23, 9);
        let mut rays = 0;
        for i in 1..64 {
            for j in 1..64 {
                // A vertex, an edge midpoint, a diagonal midpoint.
                for (dx, dy) in [(0.0, 0.0), (0.5, 0.0), (0.5, 0.5)] {
                    let target = offset + Vec3::new(i as f32 + dx, j as f32 + dy, 0.0);
                    let from = Vec3::new(
                        rng.next_f32() * 64.0,
                        rng.next_f32() * 64.0,
                        1.0 + rng.next_f32() * 30.0,
                    );
                    let ray = Ray::new(offset + from, target - (offset + from));
                    let want = brute(&mesh, &ray, f32::INFINITY).expect("brute force hits");
                    let got = accel.intersect(&ray, f32::INFINITY);
                    let got = got.unwrap_or_else(|| panic!("leak at {target:?}: {ray:?}"));
                    let close = |t: f32| (t - want.1).abs() <= 4.0 * f32::EPSILON * want.1;
                    assert!(
                        close(got.hit.t),
                        "{} against {}: {ray:?}",
                        got.hit.t,
                        want.1
                    );
                    assert!(accel.occluded(&ray, f32::INFINITY), "{ray:?}");
                    let (binary, occluded) = binary(&accel, &bvh, &ray, f32::INFINITY);
                    let binary = binary.unwrap_or_else(|| panic!("binary BVH leak: {ray:?}"));
                    assert!(
                        close(binary.1),
                        "binary BVH {} against {}",
                        binary.1,
                        want.1
                    );
                    assert!(occluded, "binary BVH any-hit, {ray:?}");
                    rays += 1;
                }
            }
        }
        assert_eq!(rays, 63 * 63 * 3);
    }
}

/// A render is a function of scene, seed and sample index only: the wide
/// BVH, built in parallel, must come out the same whatever the thread
/// count. 6·10⁵ boxes (above obvhs's thresholds for parallel sorting and
/// PLOC passes), built on one and on three threads.
#[test]
fn wide_bvh_is_the_same_on_any_thread_count() {
    let mut rng = Pcg32::new(41, 7);
    let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
    let boxes: Vec<fogbank_math::Aabb> = (0..600_000)
        .map(|_| {
            let c = v() * 100.0;
            fogbank_math::Aabb::new(c, c + v())
        })
        .collect();
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| fogbank_geometry::WideBvh::new(&boxes))
    };
    let one = build(1);
    assert!(one.node_count() > 0);
    assert!(one == build(3), "the build depends on the thread count");
}

/// Found by the `ply` fuzz target: one triangle with corners near 10¹⁹ and
/// 10²⁸ (finite, but its box's surface area overflows f32) made the wide
/// BVH's builder fail an assertion. Such boxes are left out like
/// non-finite ones: the mesh builds, and nothing hits the triangle.
#[test]
fn a_triangle_too_large_for_f32_areas_builds_and_is_left_out() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/fuzz/ply_huge_triangle.ply"
    );
    let mesh =
        fogbank_geometry::loaders::ply::parse_ply(&*std::fs::read(path).unwrap(), path).unwrap();
    let accel = MeshAccel::new(mesh);
    let ray = Ray::new(Vec3::new(0.5, 0.0, -1.0), Vec3::Z);
    assert!(accel.intersect(&ray, f32::INFINITY).is_none());
    assert!(!accel.occluded(&ray, f32::INFINITY));
}

//! The WGSL BVH traversal and watertight triangle test (bvh.wgsl) against
//! fogbank_geometry ray by ray: the same closest triangle at the same
//! distance, and the same any-hit answer, on a tessellated sphere with
//! scattered clutter, degenerate and NaN triangles; axis-parallel rays and
//! finite t_max included. Also an empty hierarchy.

use fogbank_geometry::shapes::{quad_grid, uv_sphere};
use fogbank_geometry::{MeshAccel, TriangleMesh};
use fogbank_gpu::diagnostics::{bvh_queries, BvhQuery};
use fogbank_gpu::test_gpu;
use fogbank_math::testdata::probe_ray;
use fogbank_math::{Pcg32, Ray, Vec3};

fn mesh() -> TriangleMesh {
    let sphere = uv_sphere(60, |_, _| 1.0);
    let (mut p, mut t) = (sphere.positions, sphere.triangles);
    let mut rng = Pcg32::new(2, 8);
    let v = |rng: &mut Pcg32| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
    for k in 0..5000 {
        let c = v(&mut rng) * 3.0;
        let b = p.len() as u32;
        p.push(c);
        p.push(c + v(&mut rng) * 0.1);
        p.push(if k % 500 == 0 {
            Vec3::NAN
        } else {
            c + v(&mut rng) * 0.1
        });
        t.push([b, b + 1, b + 2]);
    }
    TriangleMesh::new("sphere", p, t, vec![], vec![]).unwrap()
}

fn queries(count: u32) -> Vec<BvhQuery> {
    (0..count)
        .map(|k| {
            let (ray, t_max) = probe_ray(&mut Pcg32::new(k as u64, 3), k as usize);
            BvhQuery {
                o: ray.o.to_array(),
                t_max,
                d: ray.d.to_array(),
                pad: 0.0,
            }
        })
        .collect()
}

#[test]
fn gpu_bvh_matches_the_cpu_ray_by_ray() {
    let Some(gpu) = test_gpu() else { return };
    let accel = MeshAccel::new(mesh());
    let qs = queries(4000);
    let answers = bvh_queries(&gpu, &accel, &qs).unwrap();
    let (mut hits, mut ties) = (0, 0);
    for (k, (q, a)) in qs.iter().zip(&answers).enumerate() {
        let ray = Ray::new(Vec3::from(q.o), Vec3::from(q.d));
        let cpu = accel.intersect(&ray, q.t_max);
        assert_eq!(
            a[3] == 1,
            accel.occluded(&ray, q.t_max),
            "any hit, ray {k}: {ray:?} t_max {} gpu {a:?} t {} cpu {cpu:?}",
            q.t_max,
            f32::from_bits(a[1])
        );
        match cpu {
            None => assert_eq!(a[0], u32::MAX, "ray {k}: the GPU hit, the CPU did not"),
            Some(h) => {
                hits += 1;
                assert_ne!(a[0], u32::MAX, "ray {k}: the CPU hit, the GPU did not");
                let t = f32::from_bits(a[1]);
                assert!(
                    (t - h.hit.t).abs() <= 1e-5 * h.hit.t.max(1.0),
                    "ray {k}: t {t} vs {}",
                    h.hit.t
                );
                let tri = accel.wide.order()[a[0] as usize];
                if tri != h.primitive {
                    // Only on an edge or vertex shared at the same distance.
                    ties += 1;
                }
            }
        }
    }
    println!("{hits} hits of 4000, {ties} ties");
    assert!(hits > 2000, "{hits} hits of 4000");
    assert!(ties <= 4, "{ties} rays picked another triangle");
}

#[test]
fn empty_hierarchy_hits_nothing_on_the_gpu() {
    let Some(gpu) = test_gpu() else { return };
    let accel = MeshAccel::new(TriangleMesh::default());
    let answers = bvh_queries(&gpu, &accel, &queries(64)).unwrap();
    assert!(answers.iter().all(|a| a[0] == u32::MAX && a[3] == 0));
}

/// Rays along ±z with zero x and y direction of both signs whose origins
/// lie on the boxes' planes (slab distance 0·∞ = NaN) reach the edges and
/// corners of a grid of unit quads, as on the CPU
/// (bvh_test::axis_parallel_rays_on_box_planes_find_the_edges_they_graze).
#[test]
fn axis_parallel_rays_on_box_planes_hit_on_the_gpu() {
    let Some(gpu) = test_gpu() else { return };
    let accel = MeshAccel::new(quad_grid(8));
    let mut qs = Vec::new();
    for i in 0..=16 {
        for j in 0..=16 {
            for (dz, oz) in [(-1.0f32, 2.0f32), (1.0, -2.0)] {
                for zero in [0.0f32, -0.0] {
                    qs.push(BvhQuery {
                        o: [i as f32 * 0.5, j as f32 * 0.5, oz],
                        t_max: f32::INFINITY,
                        d: [zero, zero, dz],
                        pad: 0.0,
                    });
                }
            }
        }
    }
    let answers = bvh_queries(&gpu, &accel, &qs).unwrap();
    for (q, a) in qs.iter().zip(&answers) {
        assert_ne!(a[0], u32::MAX, "the GPU missed {q:?}");
        assert_eq!(f32::from_bits(a[1]), 2.0, "{q:?}");
        assert_eq!(a[3], 1, "any hit {q:?}");
    }
}

/// The light BVH's descent and pmf (light_bvh.wgsl) against
/// `LightSampler::pick` and `pmf` at points in the fog of 300 emitting
/// triangles: the same light for almost every (point, u) — GPU division
/// may put a u right at a child's boundary on the other side — with the
/// same probability, and the GPU's pmf re-derived along the trail equal to
/// the pick's.
#[test]
fn light_bvh_picks_match_the_cpu() {
    use fogbank_render::integrators::IntegratorKind;
    use fogbank_render::lights::sample::Vertex;
    let Some(gpu) = test_gpu() else { return };
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/mitsuba/fog_emitters.xml");
    let scene =
        fogbank_scene::load_scene(Some(&path), &["render.light_sampler=bvh".into()]).unwrap();
    let IntegratorKind::VolPath(v) = &scene.integrator else {
        panic!("volpath")
    };
    assert!(v.lights.bvh().is_some());
    let mut rng = Pcg32::new(9, 1);
    let queries: Vec<[f32; 4]> = (0..4096)
        .map(|_| {
            let r = |rng: &mut Pcg32| 6.0 * rng.next_f32() - 3.0;
            [r(&mut rng), r(&mut rng), r(&mut rng), rng.next_f32()]
        })
        .collect();
    let answers = fogbank_gpu::diagnostics::light_picks(&gpu, &scene, &queries).unwrap();
    let mut same = 0;
    for (q, a) in queries.iter().zip(&answers) {
        let p = Vec3::new(q[0], q[1], q[2]);
        let cpu = v.lights.pick(q[3], Vertex::Medium, p);
        let (pmf, pmf_at) = (f32::from_bits(a[1]), f32::from_bits(a[2]));
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * a.abs().max(b.abs());
        match cpu {
            None => {
                assert_eq!(a[0], u32::MAX, "{p}: the CPU picks nothing");
                same += 1;
            }
            Some((i, cpu_pmf)) if i as u32 == a[0] => {
                same += 1;
                assert!(
                    close(cpu_pmf, pmf),
                    "{p}: light {i} pmf cpu {cpu_pmf} gpu {pmf}"
                );
            }
            Some(_) => {}
        }
        if a[0] != u32::MAX {
            assert!(close(pmf, pmf_at), "{p}: gpu pick {pmf} vs pmf {pmf_at}");
            let cpu_pmf = v.lights.pmf(a[0] as usize, Vertex::Medium, p);
            assert!(
                close(cpu_pmf, pmf_at),
                "{p}: light {} pmf cpu {cpu_pmf} gpu {pmf_at}",
                a[0]
            );
        }
    }
    assert!(same >= 4096 * 99 / 100, "{same} of 4096 picks agree");
}

//! Surfaces' acceleration structures side by side: build time, memory and
//! closest-hit / any-hit rays per second of the binary BVH (binned SAH,
//! what the GPU traverses) and of the compressed 8-wide BVH (PLOC, what the
//! CPU traverses) on one generated mesh of over 10⁶ triangles — a bumpy,
//! finely tessellated sphere with 10⁵ small triangles scattered inside and
//! around it, so rays meet both large coherent surfaces and clutter. Both
//! use the same watertight triangle test on corners stored in leaf order.
//! Rays run on rayon's pool (2 threads on the development machine); the
//! binary BVH builds on one thread, the wide one on the pool. `--trials`
//! sets the ray count (default 10⁶). A second table sets instancing
//! against copying ([`super::bvh_instances`]).

use crate::harness::timing::clocked;
use crate::harness::Writer;
use fogbank_geometry::shapes::uv_sphere;
use fogbank_geometry::{intersect, Bvh, RayFrame, TriangleMesh, Walk, WideBvh};
use fogbank_math::{Pcg32, Ray, Vec3};
use rayon::prelude::*;

pub const DEFAULT_RAYS: u64 = 1_000_000;

/// A sphere of 2·n·2n triangles with a radial bump, plus `clutter` small
/// random triangles.
pub fn generated_mesh(n: usize, clutter: usize) -> TriangleMesh {
    let sphere = uv_sphere(n, |theta, phi| {
        1.0 + 0.05 * (7.0 * theta).sin() * (5.0 * phi).cos()
    });
    let (mut p, mut t) = (sphere.positions, sphere.triangles);
    let mut rng = Pcg32::new(3, 17);
    let v = |rng: &mut Pcg32| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
    for _ in 0..clutter {
        let c = v(&mut rng) * 3.0;
        let k = p.len() as u32;
        p.push(c);
        p.push(c + v(&mut rng) * 0.02);
        p.push(c + v(&mut rng) * 0.02);
        t.push([k, k + 1, k + 2]);
    }
    TriangleMesh::new("generated", p, t, vec![], vec![]).expect("valid indices")
}

/// Ray `k`: from a point around the mesh towards a point inside it.
fn ray(k: u64) -> Ray {
    let mut rng = Pcg32::new(k, 5);
    let r = |rng: &mut Pcg32| 2.0 * rng.next_f32() - 1.0;
    let o = Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * 2.5;
    let target = Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)) * 1.2;
    Ray::new(o, target - o)
}

/// One structure's figures on one mesh.
struct Measured {
    name: &'static str,
    triangles: usize,
    build_s: f64,
    build_threads: usize,
    nodes: usize,
    depth: usize,
    /// Nodes and leaf slots, per triangle.
    bytes_per_triangle: f64,
    hits: u64,
    closest_s: f64,
    occluded: u64,
    any_s: f64,
    /// Triangle tests per ray for closest hit and any hit.
    tests: [f64; 2],
}

/// What a structure is besides its walk: for the table.
struct Shape {
    name: &'static str,
    build_s: f64,
    build_threads: usize,
    nodes: usize,
    depth: usize,
    bytes: usize,
    order: Vec<u32>,
}

/// Every ray's closest hit and any hit through `bvh`, whose leaf slots hold
/// the triangles `shape.order`; their counts and times.
fn measure(mesh: &TriangleMesh, bvh: &(impl Walk + Sync), shape: Shape, rays: u64) -> Measured {
    let corners: Vec<[Vec3; 3]> = shape
        .order
        .iter()
        .map(|&i| mesh.corners(i as usize))
        .collect();
    // Ray k's hit (1 or 0) and, when `count`, how many triangles it tested
    // (counted in a pass of its own, so the timed ones count nothing).
    let trace = |k: u64, any: bool, count: bool| {
        let r = ray(k);
        let frame = RayFrame::new(&r);
        let mut tests = 0u64;
        let test = |slot: u32, t_max: f32| {
            if count {
                tests += 1;
            }
            let [a, b, c] = corners[slot as usize];
            intersect(&frame, a, b, c, t_max).map(|h| h.t)
        };
        let hit = match any {
            false => bvh.closest_hit(&r, f32::INFINITY, test).is_some(),
            true => bvh.any_hit(&r, f32::INFINITY, test),
        };
        (hit as u64, tests)
    };
    let run = |any: bool| {
        clocked(|| {
            (0..rays)
                .into_par_iter()
                .map(|k| trace(k, any, false).0)
                .sum::<u64>()
        })
    };
    let tests_per_ray = |any: bool| {
        let counted = rays.min(100_000);
        let tests: u64 = (0..counted)
            .into_par_iter()
            .map(|k| trace(k, any, true).1)
            .sum();
        tests as f64 / counted as f64
    };
    let (hits, closest_s) = run(false);
    let (occluded, any_s) = run(true);
    let tests = [tests_per_ray(false), tests_per_ray(true)];
    Measured {
        name: shape.name,
        triangles: mesh.len(),
        build_s: shape.build_s,
        build_threads: shape.build_threads,
        nodes: shape.nodes,
        depth: shape.depth,
        bytes_per_triangle: shape.bytes as f64 / mesh.len() as f64,
        hits,
        closest_s,
        occluded,
        any_s,
        tests,
    }
}

fn measure_binary(mesh: &TriangleMesh, bounds: &[fogbank_math::Aabb], rays: u64) -> Measured {
    let (bvh, build_s) = clocked(|| Bvh::new(bounds));
    let shape = Shape {
        name: "binary (binned SAH, baseline)",
        build_s,
        build_threads: 1,
        nodes: bvh.nodes.len(),
        depth: bvh.depth(),
        bytes: bvh.nodes.len() * 32 + bvh.order.len() * 4,
        order: bvh.order.clone(),
    };
    measure(mesh, &bvh, shape, rays)
}

fn measure_wide(mesh: &TriangleMesh, bounds: &[fogbank_math::Aabb], rays: u64) -> Measured {
    let (bvh, build_s) = clocked(|| WideBvh::new(bounds));
    let shape = Shape {
        name: "wide (PLOC + CWBVH8, CPU and GPU)",
        build_s,
        build_threads: rayon::current_num_threads(),
        nodes: bvh.node_count(),
        depth: bvh.depth(),
        bytes: bvh.memory_bytes(),
        order: bvh.order().to_vec(),
    };
    measure(mesh, &bvh, shape, rays)
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let rays = trials.unwrap_or(DEFAULT_RAYS);
    let threads = rayon::current_num_threads();
    // The 2.06 M triangles, and a small mesh (7,885 triangles, the
    // size of the Mitsuba comparison scenes' meshes) that stays in cache.
    let mut all = Vec::new();
    let mut hit_share = Vec::new();
    for (n, clutter) in [(700, 100_000), (30, 4_285)] {
        let mesh = generated_mesh(n, clutter);
        let bounds: Vec<_> = (0..mesh.len()).map(|i| mesh.triangle_bounds(i)).collect();
        let pair = [
            measure_binary(&mesh, &bounds, rays),
            measure_wide(&mesh, &bounds, rays),
        ];
        for m in &pair {
            if m.hits != pair[0].hits || m.occluded != pair[0].hits {
                return Err(format!(
                    "{} on {} triangles: {} closest hits and {} any hits where the binary BVH's closest hits are {}",
                    m.name, m.triangles, m.hits, m.occluded, pair[0].hits
                ));
            }
        }
        hit_share.push(pair[0].hits as f64 / rays as f64);
        all.extend(pair);
    }
    let mrays = |s: f64| rays as f64 / s / 1e6;
    let rows: Vec<Vec<String>> = all
        .iter()
        .map(|m| {
            vec![
                m.name.to_string(),
                m.triangles.to_string(),
                m.nodes.to_string(),
                m.depth.to_string(),
                format!("{:.1}", m.bytes_per_triangle),
                format!("{:.3}", m.build_s),
                m.build_threads.to_string(),
                threads.to_string(),
                rays.to_string(),
                format!("{:.3}", m.hits as f64 / rays as f64),
                format!("{:.3}", mrays(m.closest_s)),
                format!("{:.3}", mrays(m.any_s)),
                format!("{:.2}", m.tests[0]),
                format!("{:.2}", m.tests[1]),
            ]
        })
        .collect();
    w.csv(
        "bvh_perf.csv",
        &[
            "structure",
            "triangles",
            "nodes",
            "depth",
            "bytes_per_triangle",
            "build_s",
            "build_threads",
            "threads",
            "rays",
            "hit_share",
            "closest_mrays_s",
            "any_mrays_s",
            "closest_tests_per_ray",
            "any_tests_per_ray",
        ],
        &rows,
    )?;
    let mut text = format!(
        "Generated meshes (a bumpy sphere with small triangles scattered inside and around it), {rays} rays \
         from around each mesh towards its inside ({:.0} % and {:.0} % hit), {threads} threads; both \
         structures give the same hits.\n\n\
         | triangles | structure | build s (threads) | nodes | depth | bytes/triangle | closest Mrays/s | any Mrays/s | triangle tests per ray (closest, any) |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        100.0 * hit_share[0],
        100.0 * hit_share[1]
    );
    for m in &all {
        text += &format!(
            "| {} | {} | {:.3} ({}) | {} | {} | {:.1} | {:.2} | {:.2} | {:.1}, {:.1} |\n",
            m.triangles,
            m.name,
            m.build_s,
            m.build_threads,
            m.nodes,
            m.depth,
            m.bytes_per_triangle,
            mrays(m.closest_s),
            mrays(m.any_s),
            m.tests[0],
            m.tests[1]
        );
    }
    for pair in all.chunks(2) {
        text += &format!(
            "\n{} triangles, wide / binary: build {:.2}× faster, closest hit {:.2}×, any hit {:.2}×.",
            pair[0].triangles,
            pair[0].build_s / pair[1].build_s,
            pair[0].closest_s / pair[1].closest_s,
            pair[0].any_s / pair[1].any_s
        );
    }
    text += &instances_table(w, rays, threads)?;
    Ok(text)
}

/// The instanced-against-copied table (`bvh_instances.csv`) as markdown.
fn instances_table(w: &mut Writer, rays: u64, threads: usize) -> Result<String, String> {
    let rows = super::bvh_instances::measure(&generated_mesh(30, 4_285), rays)?;
    let mrays = |s: f64| rays as f64 / s / 1e6;
    let mut text = format!(
        "\n\nInstancing against copying: the {}-triangle mesh placed 256 times ({} triangles), \
         {rays} rays from above and around the field toward it, {threads} threads.\n\n\
         | structure | triangles | build s | MiB | bytes/triangle placed | hit share | closest Mrays/s | any Mrays/s |\n\
         |---|---|---|---|---|---|---|---|\n",
        rows[0].triangles / 256,
        rows[0].triangles
    );
    let mut csv = Vec::new();
    for r in &rows {
        let per = r.bytes as f64 / r.triangles as f64;
        text += &format!(
            "| {} | {} | {:.3} | {:.1} | {:.2} | {:.3} | {:.2} | {:.2} |\n",
            r.name,
            r.triangles,
            r.build_s,
            r.bytes as f64 / (1 << 20) as f64,
            per,
            r.hits as f64 / rays as f64,
            mrays(r.closest_s),
            mrays(r.any_s)
        );
        csv.push(vec![
            r.name.to_string(),
            r.triangles.to_string(),
            format!("{:.4}", r.build_s),
            r.bytes.to_string(),
            rays.to_string(),
            threads.to_string(),
            r.hits.to_string(),
            r.occluded.to_string(),
            format!("{:.3}", mrays(r.closest_s)),
            format!("{:.3}", mrays(r.any_s)),
        ]);
    }
    w.csv(
        "bvh_instances.csv",
        &[
            "structure",
            "triangles",
            "build_s",
            "bytes",
            "rays",
            "threads",
            "hits",
            "occluded",
            "closest_mrays_s",
            "any_mrays_s",
        ],
        &csv,
    )?;
    let [i, c] = &rows;
    text += &format!(
        "\nInstanced / copied: memory {:.4}×, build {:.3}×, closest-hit rate {:.2}×, any-hit rate {:.2}×.",
        i.bytes as f64 / c.bytes as f64,
        i.build_s / c.build_s,
        c.closest_s / i.closest_s,
        c.any_s / i.any_s
    );
    Ok(text)
}

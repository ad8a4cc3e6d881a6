//! Surfaces' acceleration structure: BVH build time and closest-hit / any-hit
//! rays per second on a generated mesh of over 10⁶ triangles — a bumpy,
//! finely tessellated sphere with 10⁵ small triangles scattered inside
//! and around it, so rays meet both large coherent surfaces and clutter.
//! Rays run on rayon's pool (2 threads on the development machine); build
//! on one thread. `--trials` sets the ray count (default 10⁶).

use crate::experiments::harness::timing::clocked;
use crate::experiments::harness::Writer;
use fogbank_geometry::shapes::uv_sphere;
use fogbank_geometry::{MeshAccel, TriangleMesh};
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

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let rays = trials.unwrap_or(DEFAULT_RAYS);
    let mesh = generated_mesh(700, 100_000);
    let triangles = mesh.len();
    let (accel, build) = clocked(|| MeshAccel::new(mesh));
    let threads = rayon::current_num_threads();

    let (hits, closest): (u64, f64) = clocked(|| {
        (0..rays)
            .into_par_iter()
            .map(|k| accel.intersect(&ray(k), f32::INFINITY).is_some() as u64)
            .sum()
    });
    let (occluded, any): (u64, f64) = clocked(|| {
        (0..rays)
            .into_par_iter()
            .map(|k| accel.occluded(&ray(k), f32::INFINITY) as u64)
            .sum()
    });
    if hits != occluded {
        return Err(format!("closest hit found {hits} hits, any hit {occluded}"));
    }
    let mrays = |s: f64| rays as f64 / s / 1e6;
    w.csv(
        "bvh_perf.csv",
        &[
            "triangles",
            "nodes",
            "depth",
            "build_s",
            "threads",
            "rays",
            "hit_share",
            "closest_mrays_s",
            "any_mrays_s",
        ],
        &[vec![
            triangles.to_string(),
            accel.bvh.nodes.len().to_string(),
            accel.bvh.depth().to_string(),
            format!("{build:.3}"),
            threads.to_string(),
            rays.to_string(),
            format!("{:.3}", hits as f64 / rays as f64),
            format!("{:.3}", mrays(closest)),
            format!("{:.3}", mrays(any)),
        ]],
    )?;
    Ok(format!(
        "BVH on a generated mesh of {triangles} triangles (bumpy sphere + 10⁵ scattered triangles): {} nodes, \
         depth {}, built in {build:.2} s on one thread. {rays} rays from around the mesh towards its inside \
         ({:.0} % hit), {threads} threads: closest hit {:.2} Mrays/s, any hit {:.2} Mrays/s.",
        accel.bvh.nodes.len(),
        accel.bvh.depth(),
        100.0 * hits as f64 / rays as f64,
        mrays(closest),
        mrays(any)
    ))
}

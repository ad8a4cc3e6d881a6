//! Instancing against copying, the second table of `bvh-perf`: one mesh
//! (`bvh-perf`'s 7,885-triangle generated mesh) placed 256 times — turned, scaled,
//! on a 16 × 16 grid with jittered heights — traced through the two-level
//! hierarchy ([`Instances`]: one BVH for the mesh, a top-level BVH over the
//! placements) and through one BVH over the 2.02 M triangles of the copies.
//! Same rays for both (from around the field toward it), checked to give
//! the same hit counts; build time, memory and rays per second.

use crate::harness::timing::clocked;
use fogbank_geometry::{Instance, Instances, MeshAccel, TriangleMesh};
use fogbank_math::{DAffine3, DVec3, Pcg32, Ray, Vec3};
use glam::DQuat;
use rayon::prelude::*;

/// Placements per side of the grid.
const SIDE: usize = 16;

/// The placements: grid cells 3 apart, a random turn, a scale in [0.6, 1.2].
fn placements() -> Vec<DAffine3> {
    let mut rng = Pcg32::new(8, 21);
    let mut r = move || rng.next_f32() as f64;
    (0..SIDE * SIDE)
        .map(|k| {
            let (i, j) = ((k % SIDE) as f64, (k / SIDE) as f64);
            let centre = DVec3::new(3.0 * (i - 7.5), r() - 0.5, 3.0 * (j - 7.5));
            let axis = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5 + 1e-3).normalize();
            let turn = DQuat::from_axis_angle(axis, std::f64::consts::TAU * r());
            DAffine3::from_scale_rotation_translation(DVec3::splat(0.6 + 0.6 * r()), turn, centre)
        })
        .collect()
}

/// Ray `k`: from above and around the field toward a point on it.
fn ray(k: u64) -> Ray {
    let mut rng = Pcg32::new(k, 9);
    let mut r = || 2.0 * rng.next_f32() - 1.0;
    let o = Vec3::new(30.0 * r(), 8.0 + 6.0 * r(), 30.0 * r());
    let target = Vec3::new(24.0 * r(), r(), 24.0 * r());
    Ray::new(o, target - o)
}

/// The copies: every placement's triangles in one mesh.
fn copies(mesh: &TriangleMesh, places: &[DAffine3]) -> TriangleMesh {
    let mut all = TriangleMesh::default();
    for m in places {
        let mut c = mesh.clone();
        c.transform(&glam::DMat4::from(*m).as_mat4());
        let v0 = all.positions.len() as u32;
        all.positions.extend(c.positions);
        all.triangles
            .extend(c.triangles.iter().map(|t| t.map(|v| v + v0)));
    }
    all
}

/// One structure's row.
pub struct Row {
    pub name: &'static str,
    pub triangles: usize,
    pub build_s: f64,
    pub bytes: usize,
    pub hits: u64,
    pub closest_s: f64,
    pub occluded: u64,
    pub any_s: f64,
}

/// How many of `rays` rays `hit` says hit, and the seconds it took.
fn count(rays: u64, hit: impl Fn(&Ray) -> bool + Sync) -> (u64, f64) {
    clocked(|| (0..rays).into_par_iter().filter(|&k| hit(&ray(k))).count() as u64)
}

/// The two rows, instanced then copied, of `mesh` placed 256 times.
pub fn measure(mesh: &TriangleMesh, rays: u64) -> Result<[Row; 2], String> {
    let places = placements();
    let (inst, inst_build) = clocked(|| {
        let group = MeshAccel::new(mesh.clone());
        let instances = places
            .iter()
            .map(|m| Instance::new(0, *m).expect("invertible"))
            .collect();
        Instances::new(vec![group], instances)
    });
    let inst = inst?;
    let (hi, ci) = count(rays, |r| {
        inst.intersect_where(r, f32::INFINITY, |_, _| true)
            .is_some()
    });
    let (oi, ai) = count(rays, |r| inst.occluded_where(r, f32::INFINITY, |_, _| true));
    let flat = copies(mesh, &places);
    let (copy, copy_build) = clocked(|| MeshAccel::new(flat));
    let (hc, cc) = count(rays, |r| copy.intersect(r, f32::INFINITY).is_some());
    let (oc, ac) = count(rays, |r| copy.occluded(r, f32::INFINITY));
    // Grazing rays may round differently in the group's space: a handful.
    let close = |a: u64, b: u64| a.abs_diff(b) * 10_000 <= rays;
    if !close(hi, hc) || !close(oi, oc) || !close(hi, oi) {
        return Err(format!(
            "instances: {hi} closest and {oi} any hits where the copies have {hc} and {oc}"
        ));
    }
    let triangles = mesh.len() * places.len();
    Ok([
        Row {
            name: "instanced (1 mesh BVH + top-level BVH over 256 placements)",
            triangles,
            build_s: inst_build,
            bytes: inst.memory_bytes(),
            hits: hi,
            closest_s: ci,
            occluded: oi,
            any_s: ai,
        },
        Row {
            name: "copied (one wide BVH over every triangle)",
            triangles,
            build_s: copy_build,
            bytes: copy.memory_bytes(),
            hits: hc,
            closest_s: cc,
            occluded: oc,
            any_s: ac,
        },
    ])
}

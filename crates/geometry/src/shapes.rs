//! Mitsuba 3's mesh-backed analytic shapes, generated in their object
//! space (the scene's `to_world` places them): `rectangle` — the square
//! [−1, 1]² in the z = 0 plane facing +z; `cube` — [−1, 1]³ with outward
//! faces, 24 vertices so that each face has its own normal and UVs
//! (`sphere` and `disk` are analytic: `crate::analytic`). Also test and
//! benchmark meshes (`uv_sphere`, `quad_grid`).

use crate::mesh::TriangleMesh;
use glam::{Vec2, Vec3};

const QUAD_UV: [Vec2; 4] = [
    Vec2::new(0.0, 0.0),
    Vec2::new(1.0, 0.0),
    Vec2::new(1.0, 1.0),
    Vec2::new(0.0, 1.0),
];

/// The unit rectangle: two triangles, counter-clockwise seen from +z.
pub fn rectangle() -> TriangleMesh {
    let p = vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    TriangleMesh::new(
        "rectangle",
        p,
        vec![[0, 1, 2], [0, 2, 3]],
        vec![Vec3::Z; 4],
        QUAD_UV.to_vec(),
    )
    .expect("valid indices")
}

/// The cube [−1, 1]³: per face two triangles, counter-clockwise seen from
/// outside.
pub fn cube() -> TriangleMesh {
    let (mut p, mut n, mut uv, mut t) = (vec![], vec![], vec![], vec![]);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut normal = Vec3::ZERO;
            normal[axis] = sign;
            // Tangents u × v = normal.
            let mut u = Vec3::ZERO;
            u[(axis + 1) % 3] = 1.0;
            let mut v = Vec3::ZERO;
            v[(axis + 2) % 3] = 1.0;
            if sign < 0.0 {
                std::mem::swap(&mut u, &mut v);
            }
            let base = p.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                p.push(normal + a * u + b * v);
                n.push(normal);
            }
            uv.extend(QUAD_UV);
            t.push([base, base + 1, base + 2]);
            t.push([base, base + 2, base + 3]);
        }
    }
    TriangleMesh::new("cube", p, t, n, uv).expect("valid indices")
}

/// A latitude–longitude sphere of 2·n·2n triangles about the origin with
/// radius `radius(θ, φ)` (bumps for benchmarks): the test and benchmark
/// mesh of the BVH. Rings at the poles are degenerate (zero-area
/// triangles), as such meshes have in the wild.
pub fn uv_sphere(n: usize, radius: impl Fn(f32, f32) -> f32) -> TriangleMesh {
    let mut p = Vec::with_capacity((n + 1) * 2 * n);
    for i in 0..=n {
        let theta = std::f32::consts::PI * i as f32 / n as f32;
        for j in 0..2 * n {
            let phi = std::f32::consts::PI * j as f32 / n as f32;
            let dir = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            p.push(radius(theta, phi) * dir);
        }
    }
    let idx = |i: usize, j: usize| (i * 2 * n + j % (2 * n)) as u32;
    let mut t = Vec::with_capacity(4 * n * n);
    for i in 0..n {
        for j in 0..2 * n {
            t.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
            t.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    TriangleMesh::new("uv sphere", p, t, vec![], vec![]).expect("valid indices")
}

/// An `n` × `n` grid of unit squares in the z = 0 plane, [0, n]², each
/// two triangles with corners of its own: many BVH boxes share planes with
/// the grid's lines (tests of axis-parallel rays on box planes).
pub fn quad_grid(n: usize) -> TriangleMesh {
    let (mut p, mut t) = (Vec::new(), Vec::new());
    for i in 0..n {
        for j in 0..n {
            let k = p.len() as u32;
            let (x, y) = (i as f32, j as f32);
            p.extend([
                Vec3::new(x, y, 0.0),
                Vec3::new(x + 1.0, y, 0.0),
                Vec3::new(x + 1.0, y + 1.0, 0.0),
                Vec3::new(x, y + 1.0, 0.0),
            ]);
            t.extend([[k, k + 1, k + 2], [k, k + 2, k + 3]]);
        }
    }
    TriangleMesh::new("quad_grid", p, t, vec![], vec![]).expect("valid indices")
}

#[cfg(test)]
mod shapes_test {
    use super::*;
    use crate::MeshAccel;
    use fogbank_math::{Pcg32, Ray};

    /// Geometric normals (from the winding) point where the shading
    /// normals do, and rays from inside the cube always leave through it
    /// exactly once (a closed, watertight surface).
    #[test]
    fn windings_match_normals_and_the_cube_is_closed() {
        for m in [rectangle(), cube()] {
            for (i, tri) in m.triangles.iter().enumerate() {
                let [a, b, c] = m.corners(i);
                let g = (b - a).cross(c - a).normalize();
                assert!(g.dot(m.normals[tri[0] as usize]) > 0.7, "triangle {i}");
            }
        }
        let cube = MeshAccel::new(cube());
        let mut rng = Pcg32::new(4, 4);
        for _ in 0..10_000 {
            let mut r = || 2.0 * rng.next_f32() - 1.0;
            let o = Vec3::new(r(), r(), r()) * 0.99;
            let d = Vec3::new(r(), r(), r());
            let h = cube
                .intersect(&Ray::new(o, d), f32::INFINITY)
                .expect("inside rays leave");
            let exit = o + h.hit.t * d;
            assert!((exit.abs().max_element() - 1.0).abs() < 1e-5, "{exit}");
        }
    }
}

//! Triangle meshes: positions, index triples and, when the file has them,
//! per-vertex normals and texture coordinates — the data the BVH, the
//! shading frames and (flattened) the GPU read.

use fogbank_math::{Aabb, Vec3};
use glam::{Mat4, Vec2};

#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    /// One per position, or empty.
    pub normals: Vec<Vec3>,
    /// One per position, or empty.
    pub uvs: Vec<Vec2>,
}

impl TriangleMesh {
    /// A mesh after checking that every index names a vertex and that the
    /// optional attributes have one entry per vertex. Errors say which
    /// triangle or attribute is at fault; `what` names the source.
    pub fn new(
        what: &str,
        positions: Vec<Vec3>,
        triangles: Vec<[u32; 3]>,
        normals: Vec<Vec3>,
        uvs: Vec<Vec2>,
    ) -> Result<TriangleMesh, String> {
        let n = positions.len();
        if let Some((i, t)) = triangles
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
        {
            return Err(format!(
                "{what}: triangle {i} names vertex {} of {n}",
                t.iter().max().unwrap()
            ));
        }
        for (name, len) in [
            ("normals", normals.len()),
            ("texture coordinates", uvs.len()),
        ] {
            if len != 0 && len != n {
                return Err(format!("{what}: {len} {name} for {n} vertices"));
            }
        }
        Ok(TriangleMesh {
            positions,
            triangles,
            normals,
            uvs,
        })
    }

    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The three corners of triangle `i`.
    #[inline]
    pub fn corners(&self, i: usize) -> [Vec3; 3] {
        let t = self.triangles[i];
        [
            self.positions[t[0] as usize],
            self.positions[t[1] as usize],
            self.positions[t[2] as usize],
        ]
    }

    /// Bounds of triangle `i` (NaN corners are left out, so a degenerate
    /// triangle still gets a box the BVH can sort).
    pub fn triangle_bounds(&self, i: usize) -> Aabb {
        let mut b = Aabb::new(Vec3::INFINITY, Vec3::NEG_INFINITY);
        for p in self.corners(i) {
            if p.is_finite() {
                b.min = b.min.min(p);
                b.max = b.max.max(p);
            }
        }
        b
    }

    /// Vertex normals for a mesh without them: per vertex, the faces'
    /// normals weighted by their angle at the vertex (Thürmer and Wüthrich,
    /// as Mitsuba regenerates them). Vertices of degenerate faces only get
    /// a zero normal (the renderer then shades with the face's own).
    pub fn angle_weighted_normals(&self) -> Vec<Vec3> {
        let mut n = vec![Vec3::ZERO; self.positions.len()];
        for (i, t) in self.triangles.iter().enumerate() {
            let p = self.corners(i);
            let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            if face == Vec3::ZERO {
                continue;
            }
            for k in 0..3 {
                let a = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
                let b = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
                let angle = a.dot(b).clamp(-1.0, 1.0).acos();
                n[t[k] as usize] += face * angle;
            }
        }
        n.iter().map(|v| v.normalize_or_zero()).collect()
    }

    /// Positions by `m`, normals by its inverse transpose (renormalised).
    pub fn transform(&mut self, m: &Mat4) {
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        let n = m.inverse().transpose();
        for v in &mut self.normals {
            *v = n.transform_vector3(*v).normalize_or_zero();
        }
    }
}

#[cfg(test)]
mod mesh_test {
    use super::*;

    #[test]
    fn indices_and_attribute_counts_are_checked() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        assert!(TriangleMesh::new("t", p.clone(), vec![[0, 1, 2]], vec![], vec![]).is_ok());
        let e = TriangleMesh::new("t.obj", p.clone(), vec![[0, 1, 3]], vec![], vec![]).unwrap_err();
        assert!(
            e.contains("t.obj") && e.contains("triangle 0") && e.contains("vertex 3"),
            "{e}"
        );
        let e = TriangleMesh::new("t", p, vec![[0, 1, 2]], vec![Vec3::Z], vec![]).unwrap_err();
        assert!(e.contains("1 normals for 3 vertices"), "{e}");
    }

    #[test]
    fn transform_moves_points_and_keeps_normals_perpendicular() {
        let mut m = TriangleMesh::new(
            "t",
            vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            vec![[0, 1, 2]],
            vec![Vec3::Z; 3],
            vec![],
        )
        .unwrap();
        m.transform(&Mat4::from_scale(Vec3::new(2.0, 1.0, 0.5)));
        assert_eq!(m.positions[1], Vec3::new(2.0, 0.0, 0.0));
        assert!((m.normals[0] - Vec3::Z).length() < 1e-6);
    }
}

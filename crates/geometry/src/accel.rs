//! A triangle mesh and analytic shapes with one hierarchy over them all:
//! closest-hit and any-hit queries. Primitive `i` is triangle `i` of the
//! mesh below `mesh.len()`, analytic shape `i − mesh.len()` from there.
//!
//! The CPU and the GPU trace the same compressed wide BVH ([`WideBvh`]):
//! the GPU's WGSL walk reads its nodes as [`WideBvh::node_words`] and the
//! corners in its leaf order ([`MeshAccel::leaf_corners`]).

use crate::analytic::AnalyticShape;
use crate::bvh::Walk;
use crate::mesh::TriangleMesh;
use crate::triangle::{intersect, RayFrame, TriangleHit};
use crate::wide::WideBvh;
use fogbank_math::{Aabb, Ray, Vec3};

/// The closest primitive a ray meets (on an analytic shape `b1 = b2 = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    pub primitive: u32,
    pub hit: TriangleHit,
}

#[derive(Clone, Debug)]
pub struct MeshAccel {
    pub mesh: TriangleMesh,
    pub analytic: Vec<AnalyticShape>,
    pub wide: WideBvh,
    /// The corners of each triangle in the wide BVH's leaf order: a leaf's
    /// triangles lie side by side, read without going through the indices
    /// (zero for analytic shapes).
    corners: Vec<[Vec3; 3]>,
}

impl MeshAccel {
    pub fn new(mesh: TriangleMesh) -> MeshAccel {
        MeshAccel::with_analytic(mesh, Vec::new())
    }

    pub fn with_analytic(mesh: TriangleMesh, analytic: Vec<AnalyticShape>) -> MeshAccel {
        let wide = WideBvh::new(&primitive_bounds(&mesh, &analytic));
        let corners = leaf_corners(&mesh, wide.order());
        MeshAccel {
            mesh,
            analytic,
            wide,
            corners,
        }
    }

    /// The corners of the triangle in each of the wide BVH's leaf slots
    /// (zero for analytic shapes): what the GPU's triangle array holds.
    pub fn leaf_corners(&self) -> &[[Vec3; 3]] {
        &self.corners
    }

    /// The boxes the hierarchy is built over: triangles, then analytic
    /// shapes (for building another hierarchy over the same primitives).
    pub fn primitive_bounds(&self) -> Vec<Aabb> {
        primitive_bounds(&self.mesh, &self.analytic)
    }

    /// Bytes of the mesh (positions, index triples, normals, UVs), the
    /// analytic shapes, the hierarchy and the leaf-order corners.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let m = &self.mesh;
        m.positions.len() * size_of::<Vec3>()
            + m.triangles.len() * size_of::<[u32; 3]>()
            + m.normals.len() * size_of::<Vec3>()
            + m.uvs.len() * size_of::<glam::Vec2>()
            + self.analytic.len() * size_of::<AnalyticShape>()
            + self.wide.memory_bytes()
            + self.corners.len() * size_of::<[Vec3; 3]>()
    }

    /// The analytic shape primitive `i` is, if it is one.
    pub fn analytic_of(&self, primitive: u32) -> Option<&AnalyticShape> {
        (primitive as usize)
            .checked_sub(self.mesh.len())
            .map(|k| &self.analytic[k])
    }

    /// The hit of `primitive`, in leaf slot `slot`, below `t_max`.
    fn test(
        &self,
        ray: &Ray,
        frame: &RayFrame,
        slot: u32,
        primitive: u32,
        t_max: f32,
    ) -> Option<TriangleHit> {
        match self.analytic_of(primitive) {
            None => {
                let [p0, p1, p2] = self.corners[slot as usize];
                intersect(frame, p0, p1, p2, t_max)
            }
            Some(a) => a.intersect(ray, t_max).map(|t| TriangleHit {
                t,
                b1: 0.0,
                b2: 0.0,
            }),
        }
    }

    /// The closest hit in `(0, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<MeshHit> {
        self.intersect_where(ray, t_max, |_| true)
    }

    /// The closest hit in `(0, t_max)` among the triangles `keep` accepts
    /// (by primitive index): the scene skips index-matched boundaries so.
    pub fn intersect_where(
        &self,
        ray: &Ray,
        t_max: f32,
        keep: impl Fn(u32) -> bool,
    ) -> Option<MeshHit> {
        let frame = RayFrame::new(ray);
        let mut best = None;
        self.wide.closest_hit(ray, t_max, |slot, t_max| {
            let primitive = self.wide.order()[slot as usize];
            if !keep(primitive) {
                return None;
            }
            let h = self.test(ray, &frame, slot, primitive, t_max)?;
            best = Some(MeshHit { primitive, hit: h });
            Some(h.t)
        })?;
        best
    }

    /// Whether any primitive lies on the ray in `(0, t_max)`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.occluded_where(ray, t_max, |_| true)
    }

    /// Whether any primitive `keep` accepts lies on the ray in `(0, t_max)`.
    pub fn occluded_where(&self, ray: &Ray, t_max: f32, keep: impl Fn(u32) -> bool) -> bool {
        let frame = RayFrame::new(ray);
        self.wide.any_hit(ray, t_max, |slot, t_max| {
            let primitive = self.wide.order()[slot as usize];
            if !keep(primitive) {
                return None;
            }
            self.test(ray, &frame, slot, primitive, t_max).map(|h| h.t)
        })
    }
}

/// The boxes of the mesh's triangles, then of the analytic shapes.
fn primitive_bounds(mesh: &TriangleMesh, analytic: &[AnalyticShape]) -> Vec<Aabb> {
    (0..mesh.len())
        .map(|i| mesh.triangle_bounds(i))
        .chain(analytic.iter().map(|a| a.bounds()))
        .collect()
}

/// Each leaf slot's triangle corners (zero for analytic shapes).
fn leaf_corners(mesh: &TriangleMesh, order: &[u32]) -> Vec<[Vec3; 3]> {
    order
        .iter()
        .map(|&i| match (i as usize) < mesh.len() {
            true => mesh.corners(i as usize),
            false => [Vec3::ZERO; 3],
        })
        .collect()
}

//! A triangle mesh with its BVH: closest-hit and any-hit queries.

use crate::bvh::Bvh;
use crate::mesh::TriangleMesh;
use crate::triangle::{intersect, RayFrame, TriangleHit};
use fogbank_math::{Ray, Vec3};

/// The closest triangle a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    pub triangle: u32,
    pub hit: TriangleHit,
}

#[derive(Clone, Debug)]
pub struct MeshAccel {
    pub mesh: TriangleMesh,
    pub bvh: Bvh,
    /// The corners of each triangle in the BVH's leaf order: a leaf's
    /// triangles lie side by side, read without going through the indices.
    corners: Vec<[Vec3; 3]>,
}

impl MeshAccel {
    pub fn new(mesh: TriangleMesh) -> MeshAccel {
        let bounds: Vec<_> = (0..mesh.len()).map(|i| mesh.triangle_bounds(i)).collect();
        let bvh = Bvh::new(&bounds);
        let corners = bvh
            .order
            .iter()
            .map(|&i| mesh.corners(i as usize))
            .collect();
        MeshAccel { mesh, bvh, corners }
    }

    /// The triangles' corners in leaf order (what the GPU's
    /// `surface_triangles` holds, slot for slot).
    pub fn leaf_corners(&self) -> &[[Vec3; 3]] {
        &self.corners
    }

    fn test(&self, frame: &RayFrame, slot: u32, t_max: f32) -> Option<TriangleHit> {
        let [p0, p1, p2] = self.corners[slot as usize];
        intersect(frame, p0, p1, p2, t_max)
    }

    /// The closest hit in `(0, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<MeshHit> {
        self.intersect_where(ray, t_max, |_| true)
    }

    /// The closest hit in `(0, t_max)` among the triangles `keep` accepts
    /// (by triangle index): the scene skips index-matched boundaries so.
    pub fn intersect_where(
        &self,
        ray: &Ray,
        t_max: f32,
        keep: impl Fn(u32) -> bool,
    ) -> Option<MeshHit> {
        let frame = RayFrame::new(ray);
        let mut best = None;
        self.bvh.closest_hit(ray, t_max, |slot, t_max| {
            let triangle = self.bvh.order[slot as usize];
            if !keep(triangle) {
                return None;
            }
            let h = self.test(&frame, slot, t_max)?;
            best = Some(MeshHit { triangle, hit: h });
            Some(h.t)
        })?;
        best
    }

    /// Whether any triangle lies on the ray in `(0, t_max)`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.occluded_where(ray, t_max, |_| true)
    }

    /// Whether any triangle `keep` accepts lies on the ray in `(0, t_max)`.
    pub fn occluded_where(&self, ray: &Ray, t_max: f32, keep: impl Fn(u32) -> bool) -> bool {
        let frame = RayFrame::new(ray);
        self.bvh.any_hit(ray, t_max, |slot, t_max| {
            if !keep(self.bvh.order[slot as usize]) {
                return None;
            }
            self.test(&frame, slot, t_max).map(|h| h.t)
        })
    }
}

//! A triangle mesh with its BVH: closest-hit and any-hit queries.

use crate::bvh::Bvh;
use crate::mesh::TriangleMesh;
use crate::triangle::{intersect, RayFrame, TriangleHit};
use fogbank_math::Ray;

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
}

impl MeshAccel {
    pub fn new(mesh: TriangleMesh) -> MeshAccel {
        let bounds: Vec<_> = (0..mesh.len()).map(|i| mesh.triangle_bounds(i)).collect();
        let bvh = Bvh::new(&bounds);
        MeshAccel { mesh, bvh }
    }

    fn test(&self, frame: &RayFrame, i: u32, t_max: f32) -> Option<TriangleHit> {
        let [p0, p1, p2] = self.mesh.corners(i as usize);
        intersect(frame, p0, p1, p2, t_max)
    }

    /// The closest hit in `(0, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<MeshHit> {
        let frame = RayFrame::new(ray);
        let mut best = None;
        self.bvh.closest_hit(ray, t_max, |i, t_max| {
            let h = self.test(&frame, i, t_max)?;
            best = Some(MeshHit {
                triangle: i,
                hit: h,
            });
            Some(h.t)
        })?;
        best
    }

    /// Whether any triangle lies on the ray in `(0, t_max)`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let frame = RayFrame::new(ray);
        self.bvh.any_hit(ray, t_max, |i, t_max| {
            self.test(&frame, i, t_max).map(|h| h.t)
        })
    }
}

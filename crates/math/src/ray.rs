//! Rays with an unnormalised direction: an affine map of a ray keeps its
//! parameter `t`, so estimators work in index space while `t` stays a world
//! distance (optical depth = ∫ σ_t dt needs world units).

use glam::{DAffine3, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub o: Vec3,
    pub d: Vec3,
}

/// The part `[t0, t1]` of a ray: what a transmittance estimator integrates
/// over and a free-flight sampler samples in (pbrt-v4's ray with its `tMax`,
/// with the start made explicit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RaySegment {
    pub ray: Ray,
    pub t0: f32,
    pub t1: f32,
}

impl RaySegment {
    pub fn new(ray: Ray, t0: f32, t1: f32) -> Self {
        RaySegment { ray, t0, t1 }
    }
}

impl Ray {
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Ray { o, d }
    }

    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + t * self.d
    }

    /// Maps the ray by an affine transform; `t` keeps its meaning.
    pub fn transformed(&self, m: &DAffine3) -> Ray {
        let o = m.transform_point3(self.o.as_dvec3()).as_vec3();
        let d = m.transform_vector3(self.d.as_dvec3()).as_vec3();
        Ray { o, d }
    }
}

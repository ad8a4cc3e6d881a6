//! Path vertices on surfaces (Lin et al. 2021 §4.2, §6.1): a walk that
//! reaches a surface before its next collision scatters there by the
//! BSDF, and next-event estimation leaves from it. Under direction reuse
//! the shifted vertex is the closest surface along the shifted ray
//! (x_{i−1}, ω_{i−1}), found again wherever the ray goes, so a surface
//! vertex stores no distance of its own. Its factor in F (and p̂) is
//! f_s(ω_o, ω_i)·|cos θ_i| in the solid-angle measure of ω_i; the walk
//! reaches it with probability T* (no collision before it), which cancels
//! against the T* that p̂'s candidate weights carry, as on medium segments.
//!
//! Only BSDFs without delta lobes take part (`restir` refuses the others):
//! the paths end by light sampling alone, which cannot find light along a
//! mirror direction.

use crate::world::surfaces::{ShadingFrame, SurfaceBsdf, SurfaceHit};
use crate::world::World;
use fogbank_math::{Ray, Vec3};

/// A path vertex on a surface: the hit, its BSDF and shading frame.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceVertex {
    pub hit: SurfaceHit,
    pub bsdf: SurfaceBsdf,
    pub frame: ShadingFrame,
}

impl SurfaceVertex {
    /// The closest surface along `ray` as a path vertex (`None`: none).
    pub fn closest(world: &World, ray: &Ray) -> Option<SurfaceVertex> {
        let surfaces = world.surfaces.as_ref()?;
        let hit = surfaces.intersect_opaque(ray, f32::INFINITY)?;
        let material = &surfaces.shapes[hit.shape as usize].material;
        Some(SurfaceVertex {
            hit,
            bsdf: material.at(hit.uv),
            frame: ShadingFrame::new(hit.ns),
        })
    }

    /// f_s·|cos θ_i| for light leaving along `wi` toward where the path
    /// arrived from along `d` (world directions): the vertex factor of
    /// Eq. 12 on a surface.
    pub fn scatter(&self, d: Vec3, wi: Vec3) -> Vec3 {
        let (wo, wi) = (self.frame.to_local(-d), self.frame.to_local(wi));
        self.bsdf.eval(wo, wi) * wi.z.abs()
    }

    /// The ray leaving the vertex along `wi` (pushed off the surface).
    pub fn leave(&self, wi: Vec3) -> Ray {
        self.hit.spawn(wi)
    }

    /// Emission of the surface back along `-d` (an emitting shape seen
    /// along `d`), zero otherwise.
    pub fn emitted(&self, world: &World, d: Vec3) -> Vec3 {
        world
            .surfaces
            .as_ref()
            .and_then(|s| s.emitted(&self.hit, d))
            .map_or(Vec3::ZERO, |(le, _)| le)
    }
}

//! The records a path step is written over (pbrt-v4 passes the sampler
//! and scene beside each `Li` call; Mitsuba 3 the scene, sampler and ray):
//! [`PathContext`], what every step of one path reads and counts, and the
//! vertex records [`MediumVertex`] and [`SurfaceVertex`], what a scattering
//! event knows about itself. Next-event estimation takes them instead of a
//! dozen loose arguments.

use super::tracking::Shadow;
use crate::lights::sample::LightSampler;
use crate::world::phase::HenyeyGreenstein;
use crate::world::surfaces::{ShadingFrame, SurfaceBsdf, SurfaceHit};
use crate::world::World;
use fogbank_math::{Pcg32, Vec3};

/// What every step of one path reads and counts besides its vertex: the
/// scene, the path's random stream, and the volume lookups made so far
/// (the cost measure of Peters 2025 §6, reported per pixel sample).
pub struct PathContext<'a> {
    pub world: &'a World,
    pub rng: &'a mut Pcg32,
    pub lookups: u32,
}

impl<'a> PathContext<'a> {
    pub fn new(world: &'a World, rng: &'a mut Pcg32) -> Self {
        PathContext {
            world,
            rng,
            lookups: 0,
        }
    }

    /// The next uniform number of the path's stream.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        self.rng.next_f32()
    }

    /// Two uniform numbers, drawn in order.
    #[inline]
    pub fn next_2d(&mut self) -> [f32; 2] {
        let u = self.rng.next_f32();
        [u, self.rng.next_f32()]
    }
}

/// How a vertex estimates direct light: the light-selection strategy, the
/// shadow rays' transmittance estimator, and whether light sampling is
/// MIS-weighted against phase/BSDF sampling (the balance heuristic) or the
/// only strategy (Lin et al. 2021's baseline, §6.1).
#[derive(Clone, Copy)]
pub struct NextEvent<'a> {
    pub lights: &'a LightSampler,
    pub shadow: Shadow<'a>,
    pub mis: bool,
}

/// A real collision in a medium: where, the direction the path travelled
/// to reach it, the medium's phase function, and the bounded medium the
/// path is in (see [`World::medium_active`]).
#[derive(Clone, Copy, Debug)]
pub struct MediumVertex {
    pub p: Vec3,
    pub d: Vec3,
    pub phase: HenyeyGreenstein,
    pub medium: Option<usize>,
}

/// A scattering surface hit: the hit, its shading frame, the direction
/// back along the path in that frame, the BSDF there, and the bounded
/// medium the path arrived in.
pub struct SurfaceVertex<'a> {
    pub hit: &'a SurfaceHit,
    pub frame: ShadingFrame,
    pub wo: Vec3,
    pub bsdf: &'a SurfaceBsdf,
    pub medium: Option<usize>,
}

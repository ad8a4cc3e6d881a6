//! Surfaces for the integrators that have no surface rules yet — `visopt`,
//! `ament` and `point_mis`: shapes are opaque black
//! occluders. A segment a surface cuts carries nothing and no surface
//! reflects or emits. `restir` uses the same visibility (in candidate
//! generation, in the reuse target p̂ and in F alike, so p̂ = 0 exactly
//! where F = 0) and the same refusal, and makes its shapes path vertices
//! (`restir::surface`). Such an image equals `volpath`'s (or `direct`'s) of
//! the same scene with every BSDF black and no emitter on the shapes, which
//! is how it is tested. Null boundaries of media and thin dielectrics need
//! `volpath`'s surface walk: those scenes are refused. A null shape that
//! bounds nothing is invisible to both.

use crate::error::SceneError;
use crate::world::surfaces::Surfaces;
use crate::world::World;
use fogbank_math::Ray;

/// Refuses worlds whose surfaces are not all opaque occluders.
pub fn check(world: &World, integrator: &str) -> Result<(), SceneError> {
    match &world.surfaces {
        Some(s) if s.shadows_walk() => Err(SceneError(format!(
            "integrator \"{integrator}\" sees [[shapes]] as opaque occluders only; null boundaries, thin dielectrics and media bounded by shapes need volpath"
        ))),
        _ => Ok(()),
    }
}

/// The distance to the first surface along `ray` (∞: none).
#[inline]
pub fn first_surface(world: &World, ray: &Ray) -> f32 {
    world
        .surfaces
        .as_ref()
        .and_then(|s| s.intersect_opaque(ray, f32::INFINITY))
        .map_or(f32::INFINITY, |h| h.t)
}

/// Whether no surface cuts `ray` in (0, t).
#[inline]
pub fn visible(world: &World, ray: &Ray, t: f32) -> bool {
    unblocked(world.surfaces.as_ref(), ray, t)
}

/// [`visible`] for code that holds the shapes alone (no shapes: always).
#[inline]
pub fn unblocked(surfaces: Option<&Surfaces>, ray: &Ray, t: f32) -> bool {
    surfaces.is_none_or(|s| !s.occluded(ray, t))
}

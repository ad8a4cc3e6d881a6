//! What every integrator that scatters needs from the scene's media: the
//! next real collision across overlapping media (free-flight sampling) and
//! the transmittance of a shadow segment.

use super::tracking::{self, Flight, Shadow};
use crate::world::World;
use fogbank_math::{Pcg32, Ray};
use std::cell::Cell;

/// The next real collision across all media: the first collision of
/// independent processes whose extinctions add. Returns (t, medium index).
pub fn next_collision(
    s: Flight,
    world: &World,
    ray: &Ray,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Option<(f32, usize)> {
    let hit: Cell<Option<(f32, usize)>> = Cell::new(None);
    let t_max = || hit.get().map_or(f32::INFINITY, |h| h.0);
    world.media_along(ray, t_max, |i| {
        let f = tracking::free_flight(s, i, &world.media[i].medium, ray, t_max(), rng);
        *lookups += f.lookups;
        if let Some(t) = f.t {
            hit.set(Some((t, i)));
        }
    });
    hit.get()
}

/// Transmittance of the segment `[0, distance]` of `ray` through every
/// medium (the product of per-medium estimates is unbiased when they are).
pub fn shadow_transmittance(
    nee: Shadow,
    world: &World,
    ray: &Ray,
    distance: f32,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> f32 {
    let mut t = 1.0;
    world.media_along(
        ray,
        || distance,
        |i| {
            let (tr, n) =
                tracking::transmittance(nee, i, &world.media[i].medium, ray, distance, rng);
            *lookups += n;
            t *= tr;
        },
    );
    t
}

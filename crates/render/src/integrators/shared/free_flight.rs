//! What every integrator that scatters needs from the scene's media: the
//! next real collision across overlapping media (free-flight sampling) and
//! the transmittance of a shadow segment.

use super::context::PathContext;
use super::tracking::{self, Flight, Shadow};
use fogbank_math::{Ray, Vec3};
use std::cell::Cell;

/// The next real collision across all media before `t_end` (the next
/// surface, or ∞): the first collision of independent processes whose
/// extinctions add. Returns (t, medium index).
/// `current` is the bounded medium the ray is in (see
/// [`World::medium_active`]).
pub fn next_collision(
    cx: &mut PathContext,
    s: Flight,
    ray: &Ray,
    t_end: f32,
    current: Option<usize>,
) -> Option<(f32, usize)> {
    let (world, rng, lookups) = (cx.world, &mut *cx.rng, &mut cx.lookups);
    let hit: Cell<Option<(f32, usize)>> = Cell::new(None);
    let t_max = || hit.get().map_or(t_end, |h| h.0);
    world.media_along(ray, t_max, |i| {
        if !world.medium_active(i, current) {
            return;
        }
        let f = tracking::free_flight(s, i, &world.media[i].medium, ray, t_max(), rng);
        *lookups += f.lookups;
        if let Some(t) = f.t {
            hit.set(Some((t, i)));
        }
    });
    hit.get()
}

/// Transmittance of the segment `[0, distance]` of `ray` through every
/// medium (the product of per-medium estimates is unbiased when they are);
/// 0 when a surface other than an index-matched boundary blocks it.
pub fn shadow_transmittance(cx: &mut PathContext, nee: Shadow, ray: &Ray, distance: f32) -> Vec3 {
    shadow_transmittance_in(cx, nee, ray, distance, None)
}

/// Index-matched boundaries a ray may cross in a row (a guard against
/// rays trapped by coincident surfaces).
pub const MAX_CROSSINGS: u32 = 1024;

/// [`shadow_transmittance`] for a ray that starts in bounded medium
/// `current`: across medium transitions (null boundaries) it continues in
/// the medium on their far side; thin dielectrics pass 1 − R′ of it.
pub fn shadow_transmittance_in(
    cx: &mut PathContext,
    nee: Shadow,
    ray: &Ray,
    distance: f32,
    current: Option<usize>,
) -> Vec3 {
    let world = cx.world;
    let Some(s) = &world.surfaces else {
        return media_transmittance(cx, nee, ray, distance, current);
    };
    if !s.shadows_walk() {
        if s.occluded(ray, distance) {
            return Vec3::ZERO;
        }
        return media_transmittance(cx, nee, ray, distance, current);
    }
    let (mut ray, mut left, mut current, mut tr) = (*ray, distance, current, Vec3::ONE);
    for _ in 0..MAX_CROSSINGS {
        let Some(h) = s.intersect(&ray, left) else {
            return tr * media_transmittance(cx, nee, &ray, left, current);
        };
        let material = &s.shapes[h.shape as usize].material;
        let Some(pass) = material.null_transmission(h.ns.dot(ray.d)) else {
            return Vec3::ZERO;
        };
        tr *= pass * media_transmittance(cx, nee, &ray, h.t, current);
        if tr == Vec3::ZERO {
            return Vec3::ZERO;
        }
        current = s.target_medium(&h, ray.d, current);
        left -= h.t;
        ray = h.spawn(ray.d);
    }
    Vec3::ZERO
}

/// Transmittance of `[0, distance]` through the media present for a ray
/// in bounded medium `current`, surfaces aside: per channel (equal
/// channels unless a medium's extinction is chromatic).
fn media_transmittance(
    cx: &mut PathContext,
    nee: Shadow,
    ray: &Ray,
    distance: f32,
    current: Option<usize>,
) -> Vec3 {
    let (world, rng, lookups) = (cx.world, &mut *cx.rng, &mut cx.lookups);
    let mut t = Vec3::ONE;
    world.media_along(
        ray,
        || distance,
        |i| {
            if !world.medium_active(i, current) {
                return;
            }
            let m = &world.media[i];
            let (tr, n) = match &m.chroma {
                None => {
                    let (tr, n) = tracking::transmittance(nee, i, &m.medium, ray, distance, rng);
                    (Vec3::splat(tr), n)
                }
                Some(c) => match tracking::transmittance_rgb(nee, &m.medium, c, ray, distance, rng)
                {
                    Some(one_walk) => one_walk,
                    None => c.transmittance(|cm| {
                        tracking::transmittance(nee, i, cm, ray, distance, rng)
                    }),
                },
            };
            *lookups += n;
            t *= tr;
        },
    );
    t
}

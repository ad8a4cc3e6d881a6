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
    shadow_transmittance_in(cx, nee, ShadowSpan::new(*ray, distance, None))
}

/// What is left of a shadow ray: `distance` along `ray` from its origin,
/// which lies in bounded medium `medium` (`None`: in none; see
/// [`World::medium_active`]).
#[derive(Clone, Copy, Debug)]
pub struct ShadowSpan {
    pub ray: Ray,
    pub distance: f32,
    pub medium: Option<usize>,
}

impl ShadowSpan {
    pub fn new(ray: Ray, distance: f32, medium: Option<usize>) -> ShadowSpan {
        ShadowSpan {
            ray,
            distance,
            medium,
        }
    }
}

/// Index-matched boundaries a ray may cross in a row (a guard against
/// rays trapped by coincident surfaces).
pub const MAX_CROSSINGS: u32 = 1024;

/// [`shadow_transmittance`] for a span that starts in a bounded medium:
/// across medium transitions (null boundaries) it continues in the medium
/// on their far side; thin dielectrics pass 1 − R′ of it.
pub fn shadow_transmittance_in(cx: &mut PathContext, nee: Shadow, span: ShadowSpan) -> Vec3 {
    let world = cx.world;
    let Some(s) = &world.surfaces else {
        return media_transmittance(cx, nee, &span);
    };
    if !s.shadows_walk() {
        if s.occluded(&span.ray, span.distance) {
            return Vec3::ZERO;
        }
        return media_transmittance(cx, nee, &span);
    }
    let (mut left, mut tr) = (span, Vec3::ONE);
    for _ in 0..MAX_CROSSINGS {
        let Some(h) = s.intersect(&left.ray, left.distance) else {
            return tr * media_transmittance(cx, nee, &left);
        };
        let material = &s.shapes[h.shape as usize].material;
        let Some(pass) = material.null_transmission(h.ns.dot(left.ray.d)) else {
            return Vec3::ZERO;
        };
        let to_hit = ShadowSpan {
            distance: h.t,
            ..left
        };
        tr *= pass * media_transmittance(cx, nee, &to_hit);
        if tr == Vec3::ZERO {
            return Vec3::ZERO;
        }
        left = ShadowSpan {
            ray: h.spawn(left.ray.d),
            distance: left.distance - h.t,
            medium: s.target_medium(&h, left.ray.d, left.medium),
        };
    }
    Vec3::ZERO
}

/// Transmittance of `span` through the media present in it, surfaces
/// aside: per channel (equal channels unless a medium's extinction is
/// chromatic).
fn media_transmittance(cx: &mut PathContext, nee: Shadow, span: &ShadowSpan) -> Vec3 {
    let (world, rng, lookups) = (cx.world, &mut *cx.rng, &mut cx.lookups);
    let (ray, distance, current) = (&span.ray, span.distance, span.medium);
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

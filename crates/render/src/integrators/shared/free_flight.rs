//! What every integrator that scatters needs from the scene's media: the
//! next real collision across overlapping media (free-flight sampling) and
//! the transmittance of a shadow segment.

use super::DistanceSampler;
use crate::world::World;
use fogbank_estimators::distance::{
    decomposition_tracking, delta_tracking, regular_tracking, FreeFlight,
};
use fogbank_estimators::{transmittance, Estimator};
use fogbank_math::{Pcg32, Ray};
use fogbank_volume::MediumView;

/// First real collision in one medium along the world ray before `t_max`.
pub fn free_flight(
    s: DistanceSampler,
    m: &fogbank_volume::Medium,
    ray: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> FreeFlight {
    let Some((r, t0, t1)) = m.to_index(ray, 0.0, t_max) else {
        return FreeFlight {
            t: None,
            lookups: 0,
        };
    };
    match (m.view(), s) {
        (MediumView::F16(v), DistanceSampler::RegularTracking) => {
            regular_tracking::sample(&v, &r, t0, t1, rng)
        }
        (MediumView::F32(v), DistanceSampler::RegularTracking) => {
            regular_tracking::sample(&v, &r, t0, t1, rng)
        }
        (MediumView::F16(v), DistanceSampler::DecompositionTracking) => {
            decomposition_tracking::sample(&v, &r, t0, t1, rng)
        }
        (MediumView::F32(v), DistanceSampler::DecompositionTracking) => {
            decomposition_tracking::sample(&v, &r, t0, t1, rng)
        }
        (MediumView::Analytic(v), DistanceSampler::DecompositionTracking) => {
            decomposition_tracking::sample(&v, &r, t0, t1, rng)
        }
        (MediumView::F16(v), _) => delta_tracking::sample(&v, &r, t0, t1, rng),
        (MediumView::F32(v), _) => delta_tracking::sample(&v, &r, t0, t1, rng),
        (MediumView::Analytic(v), _) => delta_tracking::sample(&v, &r, t0, t1, rng),
    }
}

/// The next real collision across all media: the first collision of
/// independent processes whose extinctions add. Returns (t, medium index).
pub fn next_collision(
    s: DistanceSampler,
    world: &World,
    ray: &Ray,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Option<(f32, usize)> {
    let mut hit: Option<(f32, usize)> = None;
    for (i, m) in world.media.iter().enumerate() {
        let t_max = hit.map_or(f32::INFINITY, |h| h.0);
        let f = free_flight(s, &m.medium, ray, t_max, rng);
        *lookups += f.lookups;
        if let Some(t) = f.t {
            hit = Some((t, i));
        }
    }
    hit
}

/// Transmittance of the segment `[0, distance]` of `ray` through every
/// medium (the product of per-medium estimates is unbiased when they are).
pub fn shadow_transmittance(
    nee: Estimator,
    world: &World,
    ray: &Ray,
    distance: f32,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> f32 {
    let mut t = 1.0;
    for m in &world.media {
        let e = transmittance(nee, &m.medium, ray, distance, rng);
        *lookups += e.lookups;
        t *= e.transmittance;
    }
    t
}

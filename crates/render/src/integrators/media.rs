//! What every integrator that scatters needs from the scene's media: the
//! next real collision across overlapping media (free-flight sampling), the
//! transmittance of a shadow segment, and the balance heuristic.

use crate::scene::Scene;
use fogbank_estimators::distance::{
    decomposition_tracking, delta_tracking, regular_tracking, FreeFlight,
};
use fogbank_estimators::{transmittance, Estimator};
use fogbank_math::{Pcg32, Ray};
use fogbank_volume::MediumView;

/// Free-flight distance sampler, selectable by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DistanceSampler {
    DeltaTracking,
    DecompositionTracking,
    /// Exact for nearest-filtered grids; analytic media fall back to delta tracking.
    RegularTracking,
}

impl DistanceSampler {
    pub const NAMES: &'static str = "delta_tracking, decomposition_tracking or regular_tracking";

    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "delta_tracking" => Some(DistanceSampler::DeltaTracking),
            "decomposition_tracking" => Some(DistanceSampler::DecompositionTracking),
            "regular_tracking" => Some(DistanceSampler::RegularTracking),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            DistanceSampler::DeltaTracking => "delta_tracking",
            DistanceSampler::DecompositionTracking => "decomposition_tracking",
            DistanceSampler::RegularTracking => "regular_tracking",
        }
    }
}

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
    scene: &Scene,
    ray: &Ray,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> Option<(f32, usize)> {
    let mut hit: Option<(f32, usize)> = None;
    for (i, m) in scene.media.iter().enumerate() {
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
    scene: &Scene,
    ray: &Ray,
    distance: f32,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> f32 {
    let mut t = 1.0;
    for m in &scene.media {
        let e = transmittance(nee, &m.medium, ray, distance, rng);
        *lookups += e.lookups;
        t *= e.transmittance;
    }
    t
}

/// Balance heuristic weight of strategy `a` against `b`.
#[inline]
pub fn balance(a: f32, b: f32) -> f32 {
    if a + b > 0.0 {
        a / (a + b)
    } else {
        0.0
    }
}

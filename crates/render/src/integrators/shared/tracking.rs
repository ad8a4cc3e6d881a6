//! How a ray finds its next collision ([`Flight`]) and how a shadow ray is
//! attenuated ([`Shadow`]): fogbank's unbiased samplers and estimators, the
//! fixed-step ray marching of Hansen 2025's baseline (§2.4), or pins (Hansen 2025
//! §3.4–§3.9), chosen per ray by the integrator (PinMS mixes them by depth).
//!
//! Pins and marching steps live in each medium's unit cube (its index box
//! scaled to [0, 1]³); the ray parameter stays the world ray's, so every
//! distance comes back in world units.

use super::DistanceSampler;
use crate::world::chroma::Chroma;
use fogbank_estimators::distance::{
    decomposition_tracking, delta_tracking, ray_marching, regular_tracking, FreeFlight,
};
use fogbank_estimators::pins::{Chord, Pin, PinGrid, UnitCube};
use fogbank_estimators::Estimator;
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{Medium, MediumView};
use std::sync::Arc;

/// Free-flight sampling of one ray.
#[derive(Clone, Copy, Debug)]
pub enum Flight<'a> {
    Sampler(DistanceSampler),
    /// Fixed-step ray marching, `step` in unit-cube edges.
    RayMarching {
        step: f32,
    },
    Pins(&'a PinSet),
}

/// Transmittance of one shadow segment.
#[derive(Clone, Copy, Debug)]
pub enum Shadow<'a> {
    Estimator(Estimator),
    RayMarching { step: f32 },
    Pins(&'a PinSet),
}

impl From<DistanceSampler> for Flight<'_> {
    fn from(s: DistanceSampler) -> Self {
        Flight::Sampler(s)
    }
}

impl From<Estimator> for Shadow<'_> {
    fn from(e: Estimator) -> Self {
        Shadow::Estimator(e)
    }
}

/// The pins of a scene's media (`None` for a medium without a grid, which
/// then attenuates nothing through pins) and how queries read them.
#[derive(Clone, Debug)]
pub struct PinSet {
    pub media: Vec<Option<Arc<PinGrid>>>,
    /// k of the majorant masks (§3.8).
    pub mask_iterations: u32,
    /// Fig. 4.5's unquantised pins: traced along the query ray itself at
    /// the grid's step instead of read from the grid.
    pub unquantised: bool,
}

impl PinSet {
    /// Bytes of the distinct grids (instances share theirs).
    pub fn memory_bytes(&self) -> usize {
        let mut seen: Vec<*const PinGrid> = Vec::new();
        let mut bytes = 0;
        for g in self.media.iter().flatten() {
            if !seen.contains(&Arc::as_ptr(g)) {
                seen.push(Arc::as_ptr(g));
                bytes += g.memory_bytes();
            }
        }
        bytes
    }

    /// P, the position cells per axis, of each distinct grid.
    pub fn positions(&self) -> Vec<u32> {
        let mut seen: Vec<*const PinGrid> = Vec::new();
        let mut out = Vec::new();
        for g in self.media.iter().flatten() {
            if !seen.contains(&Arc::as_ptr(g)) {
                seen.push(Arc::as_ptr(g));
                out.push(g.spec.positions);
            }
        }
        out
    }
}

/// The medium's unit cube.
pub fn unit_cube(m: &Medium) -> UnitCube {
    UnitCube::new(m.dims(), m.index_to_world.matrix3.as_mat3())
}

/// The world `ray` in `m`'s unit cube with its parameter unchanged, and the
/// part `[t0, t1]` of `[0, t_max]` inside the cube.
fn local_ray(m: &Medium, ray: &Ray, t_max: f32) -> Option<(Ray, Ray, f32, f32)> {
    let (r, t0, t1) = m.to_index(ray, 0.0, t_max)?;
    let d = m.dims();
    let inv = Vec3::new(1.0 / d[0] as f32, 1.0 / d[1] as f32, 1.0 / d[2] as f32);
    Some((r, Ray::new(r.o * inv, r.d * inv), t0, t1))
}

/// Ray-marching step in the ray parameter for a step of `step` unit-cube
/// edges along the local direction `d` (the thesis's "relative to the
/// bounding box").
#[inline]
fn parameter_step(local: &Ray, step: f32) -> f32 {
    step / local.d.length().max(1e-30)
}

impl PinSet {
    /// The pin a query on `local` from parameter `t0` reads, and the chord
    /// it reads it along: from the grid at the (jittered) start — the box
    /// entry for rays from outside, the origin inside — or traced along the
    /// ray itself when unquantised. `None` without a grid or a chord.
    fn query(
        &self,
        mi: usize,
        m: &Medium,
        local: &Ray,
        t0: f32,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Option<(Pin, Chord)> {
        let grid = self.media.get(mi)?.as_ref()?;
        let p = local.at(t0);
        if self.unquantised {
            let cube = unit_cube(m);
            let pin = match m.view() {
                MediumView::F16(v) => Pin::trace(&v, &cube, p, local.d, grid.spec.step, rng),
                MediumView::F32(v) => Pin::trace(&v, &cube, p, local.d, grid.spec.step, rng),
                MediumView::Analytic(v) => Pin::trace(&v, &cube, p, local.d, grid.spec.step, rng),
            };
            *lookups += 32;
            return Some((pin, Chord::new(local, t0)?));
        }
        let (pin, pj, dj) = grid.lookup(p, local.d, rng);
        *lookups += 1;
        // The author's code reads the jittered ray's chord (same speed).
        let jittered = Ray::new(pj, dj * local.d.length());
        Some((pin, Chord::new(&jittered, 0.0)?))
    }
}

/// First real collision in medium `mi` along the world ray before `t_max`.
pub fn free_flight(
    f: Flight,
    mi: usize,
    m: &Medium,
    ray: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> FreeFlight {
    let none = FreeFlight {
        t: None,
        lookups: 0,
    };
    match f {
        Flight::Sampler(s) => sampler_flight(s, m, ray, t_max, rng),
        Flight::RayMarching { step } => {
            let Some((r, local, t0, t1)) = local_ray(m, ray, t_max) else {
                return none;
            };
            let dt = parameter_step(&local, step);
            match m.view() {
                MediumView::F16(v) => {
                    ray_marching::sample(&v, &RaySegment::new(r, t0, t1), dt, rng)
                }
                MediumView::F32(v) => {
                    ray_marching::sample(&v, &RaySegment::new(r, t0, t1), dt, rng)
                }
                MediumView::Analytic(v) => {
                    ray_marching::sample(&v, &RaySegment::new(r, t0, t1), dt, rng)
                }
            }
        }
        Flight::Pins(set) => {
            let Some((_, local, t0, t1)) = local_ray(m, ray, t_max) else {
                return none;
            };
            let mut lookups = 0;
            let t = set
                .query(mi, m, &local, t0, rng, &mut lookups)
                .and_then(|(pin, chord)| {
                    let d = chord.distance(&pin, t1 - t0, set.mask_iterations, rng)?;
                    (t0 + d <= t1).then_some(t0 + d)
                });
            FreeFlight { t, lookups }
        }
    }
}

/// Transmittance of `[0, t_max]` of the world ray through medium `mi`:
/// (T, lookups).
pub fn transmittance(
    s: Shadow,
    mi: usize,
    m: &Medium,
    ray: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> (f32, u32) {
    match s {
        Shadow::Estimator(e) => {
            let est = fogbank_estimators::transmittance(e, m, ray, t_max, rng);
            (est.transmittance, est.lookups)
        }
        Shadow::RayMarching { step } => {
            let Some((r, local, t0, t1)) = local_ray(m, ray, t_max) else {
                return (1.0, 0);
            };
            let dt = parameter_step(&local, step);
            match m.view() {
                MediumView::F16(v) => {
                    ray_marching::transmittance(&v, &RaySegment::new(r, t0, t1), dt, rng)
                }
                MediumView::F32(v) => {
                    ray_marching::transmittance(&v, &RaySegment::new(r, t0, t1), dt, rng)
                }
                MediumView::Analytic(v) => {
                    ray_marching::transmittance(&v, &RaySegment::new(r, t0, t1), dt, rng)
                }
            }
        }
        Shadow::Pins(set) => {
            let Some((_, local, t0, t1)) = local_ray(m, ray, t_max) else {
                return (1.0, 0);
            };
            let mut lookups = 0;
            let t = set
                .query(mi, m, &local, t0, rng, &mut lookups)
                .map_or(1.0, |(pin, chord)| chord.transmittance(&pin, t1 - t0));
            (t, lookups)
        }
    }
}

/// Every channel's transmittance of `[0, t_max]` through a chromatic
/// medium of one density from one walk, when the estimator can share it
/// (`fogbank_estimators::scaled`); `None` otherwise.
pub fn transmittance_rgb(
    s: Shadow,
    m: &Medium,
    chroma: &Chroma,
    ray: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> Option<(Vec3, u32)> {
    let (Shadow::Estimator(e), Some(k)) = (s, chroma.shared_scale()) else {
        return None;
    };
    fogbank_estimators::scaled::transmittance_scaled(e, m, ray, t_max, rng, k)
        .map(|(t, n)| (Vec3::from(t), n))
}

/// First real collision in one medium along the world ray before `t_max`
/// with one of fogbank's unbiased samplers.
pub fn sampler_flight(
    s: DistanceSampler,
    m: &Medium,
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
            regular_tracking::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng).free_flight()
        }
        (MediumView::F32(v), DistanceSampler::RegularTracking) => {
            regular_tracking::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng).free_flight()
        }
        (MediumView::F16(v), DistanceSampler::DecompositionTracking) => {
            decomposition_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::F32(v), DistanceSampler::DecompositionTracking) => {
            decomposition_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::Analytic(v), DistanceSampler::DecompositionTracking) => {
            decomposition_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::F16(v), _) => delta_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng),
        (MediumView::F32(v), _) => delta_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng),
        (MediumView::Analytic(v), _) => {
            delta_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng)
        }
    }
}

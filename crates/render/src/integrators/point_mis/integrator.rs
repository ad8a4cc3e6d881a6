//! The `point_mis` integrator: per camera sample one point light chosen by
//! power, the strategy's distance samples along the camera ray, and the
//! in-scattered radiance at each (see the module documentation).

use super::params::PointMisParams;
use super::strategy::Strategy;
use crate::error::SceneError;
use crate::integrators::plugin::Integrator;
use crate::integrators::shared::context::PathContext;
use crate::integrators::shared::{balance, estimator_rng, occluders, primary_ray, PixelSample};
use crate::lights::sample::{LightSampler, Vertex};
use crate::lights::Light;
use crate::world::medium::SceneMedium;
use crate::world::phase::HenyeyGreenstein;
use crate::world::surfaces::Surfaces;
use crate::world::World;
use fogbank_estimators::distance::delta_tracking_ratio::{self, TrackedFreeFlight};
use fogbank_estimators::distance::equiangular;
use fogbank_estimators::jackknife::{optical_depths, Sampling};
use fogbank_estimators::jackknife_function::mis_weight;
use fogbank_estimators::lookup::sigma_t_at;
use fogbank_estimators::optical_depth::Jitter;
use fogbank_estimators::{ratio_tracking, transmittance, Estimator};
use fogbank_math::{Pcg32, Ray, RaySegment, SampleKey, Vec3};
use fogbank_volume::{MediumView, VolumeAccess};

#[derive(Clone, Debug)]
pub struct PointMis {
    pub strategy: Strategy,
    /// Transmittance estimator of the ray from the scattering point to the light.
    pub nee: Estimator,
    /// N of the optical-depth estimates behind the MIS weights.
    pub mis_samples: u32,
    pub lights: LightSampler,
}

impl PointMis {
    /// Builds `point_mis`, rejecting worlds it cannot render: exactly one
    /// medium, only point lights, shapes only as opaque occluders.
    pub fn new(p: &PointMisParams, world: &World) -> Result<PointMis, SceneError> {
        occluders::check(world, "point_mis")?;
        if world.media.len() != 1 {
            return Err(SceneError(format!(
                "integrator.type = \"point_mis\": needs exactly one medium, the scene has {}",
                world.media.len()
            )));
        }
        if world.lights.is_empty() {
            return Err(SceneError(
                "integrator.type = \"point_mis\": needs at least one point light".into(),
            ));
        }
        if let Some(i) = world
            .lights
            .iter()
            .position(|l| !matches!(l, Light::Point { .. }))
        {
            return Err(SceneError(format!(
                "lights.{i}: `point_mis` supports only point lights"
            )));
        }
        Ok(PointMis {
            strategy: p.strategy,
            nee: p.estimator,
            mis_samples: p.mis_samples,
            // Point-light power does not depend on the scene radius.
            lights: LightSampler::new(&world.lights, 1.0, world.light_selection),
        })
    }
}

impl Integrator for PointMis {
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let mut rng = estimator_rng(key);
        let Some((seg, pmf)) = self.begin(world, x, y, key, &mut rng) else {
            return PixelSample::default();
        };
        let cx = &mut PathContext::new(world, &mut rng);
        let medium = seg.medium;
        let l = match medium.medium.view() {
            MediumView::F16(v) => self.radiance(&v, &seg, cx),
            MediumView::F32(v) => self.radiance(&v, &seg, cx),
            MediumView::Analytic(v) => self.radiance(&v, &seg, cx),
        };
        PixelSample {
            radiance: l / pmf,
            lookups: cx.lookups,
        }
    }

    fn estimator(&self) -> Option<Estimator> {
        Some(self.nee)
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        Some(&mut self.nee)
    }

    fn occluders_only(&self) -> bool {
        true
    }
}

/// What every distance sample of one pixel sample shares.
pub(super) struct Segment<'a> {
    pub(super) medium: &'a SceneMedium,
    /// World-space camera ray (unit direction) and the same ray in index
    /// space; both share the parameter t.
    pub(super) world: Ray,
    pub(super) index: Ray,
    /// The camera ray's parameter range inside the medium's box.
    pub(super) a: f32,
    pub(super) b: f32,
    pub(super) light: Vec3,
    pub(super) intensity: Vec3,
    pub(super) hg: HenyeyGreenstein,
    /// The scene's shapes: opaque occluders of light rays
    /// (`shared/occluders.rs`).
    pub(super) surfaces: Option<&'a Surfaces>,
}

impl PointMis {
    /// The camera ray of a pixel sample inside the medium and the point
    /// light chosen for it (one draw of `rng`): the segment and the light's
    /// selection probability, or `None` when the sample adds nothing.
    pub(super) fn begin<'a>(
        &self,
        world: &'a World,
        x: u32,
        y: u32,
        key: SampleKey,
        rng: &mut Pcg32,
    ) -> Option<(Segment<'a>, f32)> {
        let medium = world.media.first()?;
        let ray = primary_ray(world, x, y, key);
        // The camera ray's medium segment ends at the first surface (or the
        // far clip plane).
        let t_end = occluders::first_surface(world, &ray).min(world.camera.ray_end(&ray));
        let (index, a, b) = medium.medium.to_index(&ray, 0.0, t_end)?;
        let (li, pmf) = self.lights.pick(rng.next_f32(), Vertex::Medium, ray.o)?;
        let Light::Point {
            position,
            intensity,
        } = world.lights[li]
        else {
            return None;
        };
        if pmf <= 0.0 {
            return None;
        }
        let seg = Segment {
            medium,
            world: ray,
            index,
            a,
            b,
            light: position,
            intensity,
            hg: medium.phase,
            surfaces: world.surfaces.as_ref(),
        };
        Some((seg, pmf))
    }

    /// L_s(t): single-scattered radiance towards the camera at parameter `t`
    /// from the chosen light (albedo · phase · I/d² · T_l), with the light
    /// ray's transmittance T_l estimated by `self.nee`.
    pub(super) fn in_scattered(&self, s: &Segment, t: f32, cx: &mut PathContext) -> Vec3 {
        let p = s.world.at(t);
        let to_light = s.light - p;
        let dist2 = to_light.length_squared();
        if !(dist2 > 0.0 && dist2.is_finite()) {
            return Vec3::ZERO;
        }
        let dist = dist2.sqrt();
        let wi = to_light / dist;
        let f = s.hg.eval(s.world.d.dot(wi));
        let light_ray = Ray::new(p, wi);
        if f <= 0.0 || !occluders::unblocked(s.surfaces, &light_ray, dist) {
            return Vec3::ZERO;
        }
        let e = transmittance(self.nee, &s.medium.medium, &light_ray, dist, cx.rng);
        cx.lookups += e.lookups;
        s.medium.albedo_at(p) * s.intensity * (f * e.transmittance / dist2)
    }

    /// Two optical-depth estimates X0, X1 of [a, t] (Peters 2025 Alg. 2, Alg. 1
    /// with Eq. 5 importance, N lookups each) — or, for the naive weight, one
    /// estimate of 2N lookups in `x[0]` and `x[1] = x[0]` so that S = 0 and
    /// App. F's formula reduces to g(X).
    pub(super) fn depths<V: VolumeAccess>(
        &self,
        v: &V,
        s: &Segment,
        t: f32,
        naive: bool,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> (f64, f64) {
        depths_n(v, s, t, self.mis_samples, naive, rng, lookups)
    }

    /// σ_t at parameter t (one lookup).
    pub(super) fn segment_sigma_t<V: VolumeAccess>(
        v: &V,
        s: &Segment,
        t: f32,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> f32 {
        sigma_t_at(v, s.index.at(t), rng, lookups)
    }

    /// σ_t at a distance t drawn by Eq. 10: `known_mu` where the strategy
    /// that drew it already knows it (and the lookup is not jittered), else
    /// one lookup.
    pub(super) fn collision_sigma_t<V: VolumeAccess>(
        v: &V,
        s: &Segment,
        t: f32,
        known_mu: Option<f32>,
        cx: &mut PathContext,
    ) -> f32 {
        match known_mu {
            Some(m) if !v.needs_jitter() => m,
            _ => Self::segment_sigma_t(v, s, t, cx.rng, &mut cx.lookups),
        }
    }

    fn radiance<V: VolumeAccess>(&self, v: &V, s: &Segment, cx: &mut PathContext) -> Vec3 {
        match self.strategy {
            Strategy::FreeFlight => self.free_flight(v, s, cx),
            Strategy::Equiangular => self.equiangular(v, s, cx),
            Strategy::MisMiller => self.mis_miller(v, s, cx),
            Strategy::MisJackknife => self.mis_jackknife(v, s, cx),
            Strategy::MisNaive | Strategy::MisJackknifeBiased => self.mis_eq10(v, s, cx),
        }
    }

    /// Free-flight sampling of the scattering distance.
    fn free_flight<V: VolumeAccess>(&self, v: &V, s: &Segment, cx: &mut PathContext) -> Vec3 {
        let mut total = Vec3::ZERO;
        let f = tracked_flight(v, s, cx);
        if let Some(t1) = f.t {
            total += self.in_scattered(s, t1, cx);
        }
        total
    }

    /// Equiangular sampling toward the point light.
    fn equiangular<V: VolumeAccess>(&self, v: &V, s: &Segment, cx: &mut PathContext) -> Vec3 {
        let Some(e) = equiangular_vertex(v, s, cx) else {
            return Vec3::ZERO;
        };
        self.in_scattered(s, e.t, cx) * (e.transmittance * e.sigma_t / e.pdf)
    }

    /// Both samples MIS-combined with weights from ratio-tracked transmittance (Miller et al. 2019).
    fn mis_miller<V: VolumeAccess>(&self, v: &V, s: &Segment, cx: &mut PathContext) -> Vec3 {
        let p0 = |t: f32| equiangular::pdf(&s.world, s.light, s.a, s.b, t);
        let mut total = Vec3::ZERO;
        // Free-flight sample: w1 = μ T_rt / (p0 + μ T_rt) with T_rt from
        // delta tracking's null collisions before t1 (Peters 2025 §6.2).
        let f = tracked_flight(v, s, cx);
        if let Some(t1) = f.t {
            let w1 = balance(f.sigma_t * f.ratio, p0(t1));
            if w1 > 0.0 {
                total += self.in_scattered(s, t1, cx) * w1;
            }
        }
        // Equiangular sample: one ratio-tracking walk over [a, t0]
        // gives both T(t0) and the weight; w0 T μ / p0 = q/(p0 + q).
        if let Some(e) = equiangular_vertex(v, s, cx) {
            let c = balance(e.sigma_t * e.transmittance, e.pdf);
            if c != 0.0 {
                total += self.in_scattered(s, e.t, cx) * c;
            }
        }
        total
    }

    /// Both samples MIS-combined with jackknife weight estimates (Peters 2025, Eq. 9).
    fn mis_jackknife<V: VolumeAccess>(&self, v: &V, s: &Segment, cx: &mut PathContext) -> Vec3 {
        let p0 = |t: f32| equiangular::pdf(&s.world, s.light, s.a, s.b, t);
        let mut total = Vec3::ZERO;
        // Peters 2025, Eq. 9. Every weight uses its own optical-depth
        // estimates and σ_t lookup, independent of the distance
        // sample and of T̃(t0), as App. D's proof needs.
        let f = tracked_flight(v, s, cx);
        if let Some(t1) = f.t {
            // The value read by delta tracking is correlated with the
            // acceptance under stochastic filtering; read afresh.
            let sigma_t = if v.needs_jitter() {
                Self::segment_sigma_t(v, s, t1, cx.rng, &mut cx.lookups)
            } else {
                f.sigma_t
            };
            let (x0, x1) = self.depths(v, s, t1, false, cx.rng, &mut cx.lookups);
            let (sigma_t, p) = (sigma_t as f64, p0(t1) as f64);
            let w1 = mis_weight(sigma_t, 0.0, sigma_t, p, x0, x1) as f32;
            if w1 != 0.0 && w1.is_finite() {
                total += self.in_scattered(s, t1, cx) * w1;
            }
        }
        if let Some((t0, pdf0)) = equiangular_distance(s, cx) {
            let sigma_t_w = Self::segment_sigma_t(v, s, t0, cx.rng, &mut cx.lookups);
            let sigma_t = if v.needs_jitter() {
                Self::segment_sigma_t(v, s, t0, cx.rng, &mut cx.lookups)
            } else {
                sigma_t_w
            };
            if sigma_t > 0.0 {
                let (x0, x1) = self.depths(v, s, t0, false, cx.rng, &mut cx.lookups);
                let (mw, p) = (sigma_t_w as f64, pdf0 as f64);
                let w0 = mis_weight(0.0, p, mw, p, x0, x1) as f32;
                let c = w0 * transmittance_to(v, s, t0, cx) * sigma_t / pdf0;
                if c != 0.0 && c.is_finite() {
                    total += self.in_scattered(s, t0, cx) * c;
                }
            }
        }
        total
    }

    /// Peters 2025, Eq. 10: the weighting function estimated at both samples.
    fn mis_eq10<V: VolumeAccess>(&self, v: &V, s: &Segment, cx: &mut PathContext) -> Vec3 {
        let mut total = Vec3::ZERO;
        // Peters 2025, Eq. 10: both samples contribute g̃(τ(t_j)) L_s(t_j)
        // with g(τ) = μ e^{−τ}/(p0 + μ e^{−τ}) (Eq. 11), estimated by
        // Eq. 12 (jackknife) or g(X) (naive, m = 1).
        let naive = self.strategy == Strategy::MisNaive;
        let ts = eq10_distances(v, s, cx.rng, &mut cx.lookups);
        for (t, p, known_mu) in ts.into_iter().flatten() {
            let sigma_t = Self::collision_sigma_t(v, s, t, known_mu, cx);
            if sigma_t <= 0.0 {
                continue;
            }
            let (x0, x1) = self.depths(v, s, t, naive, cx.rng, &mut cx.lookups);
            let m = sigma_t as f64;
            let g = mis_weight(m, 0.0, m, p as f64, x0, x1) as f32;
            if g != 0.0 && g.is_finite() {
                total += self.in_scattered(s, t, cx) * g;
            }
        }
        total
    }
}

/// [`PointMis::depths`] with an explicit N.
pub(super) fn depths_n<V: VolumeAccess>(
    v: &V,
    s: &Segment,
    t: f32,
    mis_samples: u32,
    naive: bool,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> (f64, f64) {
    let mut x = [0.0f64; 2];
    let (n, out) = if naive {
        (2 * mis_samples, &mut x[..1])
    } else {
        (mis_samples, &mut x[..])
    };
    let sampling = Sampling::fixed_count(n, Jitter::Stratified);
    optical_depths(
        v,
        &RaySegment::new(s.index, s.a, t),
        sampling,
        rng,
        lookups,
        out,
    );
    if naive {
        (x[0], x[0])
    } else {
        (x[0], x[1])
    }
}

/// A free-flight distance by delta tracking over the camera segment, with
/// the ratio of its null collisions (its lookups counted).
fn tracked_flight<V: VolumeAccess>(v: &V, s: &Segment, cx: &mut PathContext) -> TrackedFreeFlight {
    let f = delta_tracking_ratio::sample(v, &RaySegment::new(s.index, s.a, s.b), cx.rng);
    cx.lookups += f.lookups;
    f
}

/// An equiangular distance toward the light with its pdf; `None` when the
/// pdf is zero or not finite.
fn equiangular_distance(s: &Segment, cx: &mut PathContext) -> Option<(f32, f32)> {
    let (t, pdf) = equiangular::sample(&s.world, s.light, s.a, s.b, cx.next_f32());
    (pdf > 0.0 && pdf.is_finite()).then_some((t, pdf))
}

/// An equiangular vertex: its distance `t` and `pdf`, σ_t there and the
/// transmittance from the segment's start by ratio tracking.
struct EquiangularVertex {
    t: f32,
    pdf: f32,
    sigma_t: f32,
    transmittance: f32,
}

/// An equiangular distance with σ_t and the ratio-tracked transmittance up
/// to it; `None` where no distance was drawn or σ_t is zero there.
fn equiangular_vertex<V: VolumeAccess>(
    v: &V,
    s: &Segment,
    cx: &mut PathContext,
) -> Option<EquiangularVertex> {
    let (t, pdf) = equiangular_distance(s, cx)?;
    let sigma_t = PointMis::segment_sigma_t(v, s, t, cx.rng, &mut cx.lookups);
    if sigma_t <= 0.0 {
        return None;
    }
    Some(EquiangularVertex {
        t,
        pdf,
        sigma_t,
        transmittance: transmittance_to(v, s, t, cx),
    })
}

/// T from the segment's start to `t` by ratio tracking, its lookups
/// counted.
fn transmittance_to<V: VolumeAccess>(v: &V, s: &Segment, t: f32, cx: &mut PathContext) -> f32 {
    let tr = ratio_tracking::transmittance(v, &RaySegment::new(s.index, s.a, t), cx.rng, 0.0);
    cx.lookups += tr.lookups;
    tr.transmittance
}

/// Peters 2025 Eq. 10's two distance samples, drawn in this order: the
/// free-flight one (t, p0(t), σ_t read by delta tracking) and the
/// equiangular one (t, its pdf); `None` where a strategy produced nothing.
pub(super) fn eq10_distances<V: VolumeAccess>(
    v: &V,
    s: &Segment,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> [Option<(f32, f32, Option<f32>)>; 2] {
    let f = delta_tracking_ratio::sample(v, &RaySegment::new(s.index, s.a, s.b), rng);
    *lookups += f.lookups;
    let (t0, pdf0) = equiangular::sample(&s.world, s.light, s.a, s.b, rng.next_f32());
    let mut ts = [None, None];
    if let Some(t1) = f.t {
        ts[0] = Some((
            t1,
            equiangular::pdf(&s.world, s.light, s.a, s.b, t1),
            Some(f.sigma_t),
        ));
    }
    if pdf0 > 0.0 && pdf0.is_finite() {
        ts[1] = Some((t0, pdf0, None));
    }
    ts
}

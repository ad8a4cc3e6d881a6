//! `point_mis`: single scattering from point lights inside one medium,
//! with the distance-sampling strategies of seed 000 §5 and §6.2 (Fig. 12).
//!
//! Per camera sample one point light is chosen in proportion to its power
//! ([`LightSampler`]; for point lights 4π·luminance(I)) and both distance
//! samples of the MIS strategies estimate the single-scattering integral of
//! that light (seed 000 Eq. 2 truncated to one bounce),
//!
//! ```text
//! L = ∫_a^b T(t) μ(t) L_s(t) dt,   L_s(t) = α ρ(cos θ) I T_l(t) / d(t)²,
//! ```
//!
//! divided by the light's selection probability. `T_l`, the transmittance
//! from the scattering point to the light, uses the integrator's `estimator`
//! (seed 000 Fig. 12 uses the jackknife there). Where a strategy needs T(t0)
//! along the camera ray at an equiangular sample it uses ratio tracking, the
//! unbiased estimator that §5.2 asks for and that Miller et al.'s MIS reuses.
//! The MIS strategies take two distance samples per pixel sample (the paper
//! counts "16 spp, but for MIS that amounts to 32 distance samples").
//!
//! Only point lights and exactly one medium are supported: the free-flight
//! pdf T(t)μ(t) of overlapping media would need the summed extinction in
//! every optical-depth estimate; [`settings`] rejects other scenes.

use super::{dim, primary_ray, PixelSample};
use crate::desc::{SceneDesc, SceneError};
use crate::lights::sample::LightSampler;
use crate::phase::HenyeyGreenstein;
use crate::scene::{Light, Scene, SceneMedium};
use fogbank_estimators::distance::{delta_tracking_ratio, equiangular};
use fogbank_estimators::jackknife::{optical_depths, StepMode};
use fogbank_estimators::jackknife_function::mis_weight;
use fogbank_estimators::lookup::sigma_t;
use fogbank_estimators::optical_depth::{Importance, Jitter};
use fogbank_estimators::{ratio_tracking, transmittance, Estimator};
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};
use fogbank_volume::{Filter, MediumView, VolumeAccess};

/// How distances along the camera ray are sampled and combined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Delta tracking; T(t)μ(t) cancels with its density (seed 000 §2.1).
    FreeFlight,
    /// Kulla & Fajardo 2012 towards the chosen light; T(t0) by ratio tracking.
    Equiangular,
    /// Balance heuristic with Miller et al. 2019's weights: μ T_rt/(p0 + μ T_rt)
    /// with T_rt from delta tracking's own null collisions (seed 000 §6.2).
    MisMiller,
    /// Eq. 10 with the naive weight g(X) of one optical-depth estimate
    /// (m = 1, 2N lookups, the same cost as two of N). Biased.
    MisNaive,
    /// Eq. 9 with jackknife weights Re g(X̄ + iS) (Eq. 12, App. F) and an
    /// independent ratio-tracking estimate of T(t0). Unbiased (App. D).
    MisJackknife,
    /// Eq. 10: jackknife weights that also carry the transmittance. Biased.
    MisJackknifeBiased,
}

impl Strategy {
    pub const ALL: [Strategy; 6] = [
        Strategy::FreeFlight,
        Strategy::Equiangular,
        Strategy::MisMiller,
        Strategy::MisNaive,
        Strategy::MisJackknife,
        Strategy::MisJackknifeBiased,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Strategy::FreeFlight => "free_flight",
            Strategy::Equiangular => "equiangular",
            Strategy::MisMiller => "mis_miller",
            Strategy::MisNaive => "mis_naive",
            Strategy::MisJackknife => "mis_jackknife",
            Strategy::MisJackknifeBiased => "mis_jackknife_biased",
        }
    }

    pub fn parse(s: &str) -> Option<Strategy> {
        Strategy::ALL.into_iter().find(|k| k.name() == s)
    }

    /// Whether the expected radiance differs from the single-scattering
    /// integral (given an unbiased light-ray `estimator`).
    pub fn biased(self) -> bool {
        matches!(self, Strategy::MisNaive | Strategy::MisJackknifeBiased)
    }

    /// Distance samples per pixel sample.
    pub fn distance_samples(self) -> u32 {
        match self {
            Strategy::FreeFlight | Strategy::Equiangular => 1,
            _ => 2,
        }
    }
}

/// Default N, lookups per optical-depth estimate of the MIS weights (seed
/// 000 §6.2: "our optical-depth estimator with N = 10").
pub const DEFAULT_MIS_SAMPLES: u32 = 10;

#[derive(Clone, Debug)]
pub struct PointMis {
    pub strategy: Strategy,
    /// Transmittance estimator of the ray from the scattering point to the light.
    pub nee: Estimator,
    /// N of the optical-depth estimates behind the MIS weights.
    pub mis_samples: u32,
    pub lights: LightSampler,
}

/// Builds `point_mis` from `[integrator]`, rejecting what it cannot render.
pub fn settings(
    desc: &SceneDesc,
    media: &[SceneMedium],
    lights: &[Light],
) -> Result<PointMis, SceneError> {
    let d = &desc.integrator;
    let name = d.strategy.as_deref().unwrap_or("mis_jackknife");
    let strategy = Strategy::parse(name).ok_or_else(|| {
        SceneError(format!(
            "integrator.strategy: unknown strategy `{name}` (available: {})",
            Strategy::ALL.map(Strategy::name).join(", ")
        ))
    })?;
    for (key, set) in [
        ("distance_sampler", d.distance_sampler.is_some()),
        ("max_depth", d.max_depth.is_some()),
        ("rr_depth", d.rr_depth.is_some()),
        ("preset", d.preset.is_some()),
    ] {
        if set {
            return Err(SceneError(format!(
                "integrator.{key}: not used by `point_mis` (single scattering with its own distance sampling)"
            )));
        }
    }
    if media.len() != 1 {
        return Err(SceneError(format!(
            "integrator.type = \"point_mis\": needs exactly one medium, the scene has {}",
            media.len()
        )));
    }
    if lights.is_empty() {
        return Err(SceneError(
            "integrator.type = \"point_mis\": needs at least one point light".into(),
        ));
    }
    if let Some(i) = lights
        .iter()
        .position(|l| !matches!(l, Light::Point { .. }))
    {
        return Err(SceneError(format!(
            "lights.{i}: `point_mis` supports only point lights"
        )));
    }
    let mis_samples = d.mis_samples.unwrap_or(DEFAULT_MIS_SAMPLES);
    if mis_samples == 0 || mis_samples > 4096 {
        return Err(SceneError(format!(
            "integrator.mis_samples: {mis_samples} is outside 1..=4096"
        )));
    }
    let nee = Estimator::with_options(&d.estimator, &d.estimator_options())
        .map_err(|e| SceneError(format!("integrator.estimator: {e}")))?;
    Ok(PointMis {
        strategy,
        nee,
        mis_samples,
        // Point-light power does not depend on the scene radius.
        lights: LightSampler::new(lights, 1.0),
    })
}

/// What every distance sample of one pixel sample shares.
struct Segment<'a> {
    medium: &'a SceneMedium,
    /// World-space camera ray (unit direction) and the same ray in index
    /// space; both share the parameter t.
    world: Ray,
    index: Ray,
    /// The camera ray's parameter range inside the medium's box.
    a: f32,
    b: f32,
    light: Vec3,
    intensity: Vec3,
    hg: HenyeyGreenstein,
}

/// Balance weight of a known positive density `q` against `p`, guarded so a
/// zero or non-finite denominator contributes nothing rather than NaN.
fn balance(q: f32, p: f32) -> f32 {
    let d = q + p;
    if d > 0.0 && d.is_finite() {
        q / d
    } else {
        0.0
    }
}

impl PointMis {
    pub fn sample(&self, scene: &Scene, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let mut rng = SampleKey {
            dimension: dim::ESTIMATOR,
            ..key
        }
        .rng();
        let world = primary_ray(scene, x, y, key);
        let mut lookups = 0u32;
        let zero = PixelSample::default();
        let Some(medium) = scene.media.first() else {
            return zero;
        };
        let Some((index, a, b)) = medium.medium.to_index(&world, 0.0, f32::INFINITY) else {
            return zero;
        };
        let Some((li, pmf)) = self.lights.pick(rng.next_f32()) else {
            return zero;
        };
        let Light::Point {
            position,
            intensity,
        } = scene.lights[li]
        else {
            return zero;
        };
        if pmf <= 0.0 {
            return zero;
        }
        let seg = Segment {
            medium,
            world,
            index,
            a,
            b,
            light: position,
            intensity,
            hg: HenyeyGreenstein { g: medium.phase_g },
        };
        let l = match medium.medium.view() {
            MediumView::F16(v) => self.radiance(&v, &seg, &mut rng, &mut lookups),
            MediumView::F32(v) => self.radiance(&v, &seg, &mut rng, &mut lookups),
            MediumView::Analytic(v) => self.radiance(&v, &seg, &mut rng, &mut lookups),
        };
        PixelSample {
            radiance: l / pmf,
            lookups,
        }
    }

    /// L_s(t): single-scattered radiance towards the camera at parameter `t`
    /// from the chosen light (albedo · phase · I/d² · T_l), with the light
    /// ray's transmittance T_l estimated by `self.nee`.
    fn in_scattered(&self, s: &Segment, t: f32, rng: &mut Pcg32, lookups: &mut u32) -> Vec3 {
        let p = s.world.at(t);
        let to_light = s.light - p;
        let dist2 = to_light.length_squared();
        if !(dist2 > 0.0 && dist2.is_finite()) {
            return Vec3::ZERO;
        }
        let dist = dist2.sqrt();
        let wi = to_light / dist;
        let f = s.hg.eval(s.world.d.dot(wi));
        if f <= 0.0 {
            return Vec3::ZERO;
        }
        let e = transmittance(self.nee, &s.medium.medium, &Ray::new(p, wi), dist, rng);
        *lookups += e.lookups;
        s.medium.albedo_at(p) * s.intensity * (f * e.transmittance / dist2)
    }

    /// Two optical-depth estimates X0, X1 of [a, t] (seed 000 Alg. 2, Alg. 1
    /// with Eq. 5 importance, N lookups each) — or, for the naive weight, one
    /// estimate of 2N lookups in `x[0]` and `x[1] = x[0]` so that S = 0 and
    /// App. F's formula reduces to g(X).
    fn depths<V: VolumeAccess>(
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
    fn mu<V: VolumeAccess>(v: &V, s: &Segment, t: f32, rng: &mut Pcg32, lookups: &mut u32) -> f32 {
        sigma_t(v, s.index.at(t), rng, lookups)
    }

    fn radiance<V: VolumeAccess>(
        &self,
        v: &V,
        s: &Segment,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> Vec3 {
        let p0 = |t: f32| equiangular::pdf(&s.world, s.light, s.a, s.b, t);
        let mut total = Vec3::ZERO;
        match self.strategy {
            Strategy::FreeFlight => {
                let f = delta_tracking_ratio::sample(v, &s.index, s.a, s.b, rng);
                *lookups += f.lookups;
                if let Some(t1) = f.t {
                    total += self.in_scattered(s, t1, rng, lookups);
                }
            }
            Strategy::Equiangular => {
                let (t0, pdf0) = equiangular::sample(&s.world, s.light, s.a, s.b, rng.next_f32());
                if pdf0 > 0.0 && pdf0.is_finite() {
                    let mu = Self::mu(v, s, t0, rng, lookups);
                    if mu > 0.0 {
                        let tr = ratio_tracking::transmittance(v, &s.index, s.a, t0, rng);
                        *lookups += tr.lookups;
                        let l = self.in_scattered(s, t0, rng, lookups);
                        total += l * (tr.transmittance * mu / pdf0);
                    }
                }
            }
            Strategy::MisMiller => {
                // Free-flight sample: w1 = μ T_rt / (p0 + μ T_rt) with T_rt from
                // delta tracking's null collisions before t1 (seed 000 §6.2).
                let f = delta_tracking_ratio::sample(v, &s.index, s.a, s.b, rng);
                *lookups += f.lookups;
                if let Some(t1) = f.t {
                    let w1 = balance(f.mu * f.ratio, p0(t1));
                    if w1 > 0.0 {
                        total += self.in_scattered(s, t1, rng, lookups) * w1;
                    }
                }
                // Equiangular sample: one ratio-tracking walk over [a, t0]
                // gives both T(t0) and the weight; w0 T μ / p0 = q/(p0 + q).
                let (t0, pdf0) = equiangular::sample(&s.world, s.light, s.a, s.b, rng.next_f32());
                if pdf0 > 0.0 && pdf0.is_finite() {
                    let mu = Self::mu(v, s, t0, rng, lookups);
                    if mu > 0.0 {
                        let tr = ratio_tracking::transmittance(v, &s.index, s.a, t0, rng);
                        *lookups += tr.lookups;
                        let c = balance(mu * tr.transmittance, pdf0);
                        if c != 0.0 {
                            total += self.in_scattered(s, t0, rng, lookups) * c;
                        }
                    }
                }
            }
            Strategy::MisJackknife => {
                // Seed 000, Eq. 9. Every weight uses its own optical-depth
                // estimates and σ_t lookup, independent of the distance
                // sample and of T̃(t0), as App. D's proof needs.
                let f = delta_tracking_ratio::sample(v, &s.index, s.a, s.b, rng);
                *lookups += f.lookups;
                if let Some(t1) = f.t {
                    // The value read by delta tracking is correlated with the
                    // acceptance under stochastic filtering; read afresh.
                    let mu = if v.needs_jitter() {
                        Self::mu(v, s, t1, rng, lookups)
                    } else {
                        f.mu
                    };
                    let (x0, x1) = self.depths(v, s, t1, false, rng, lookups);
                    let (mu, p) = (mu as f64, p0(t1) as f64);
                    let w1 = mis_weight(mu, 0.0, mu, p, x0, x1) as f32;
                    if w1 != 0.0 && w1.is_finite() {
                        total += self.in_scattered(s, t1, rng, lookups) * w1;
                    }
                }
                let (t0, pdf0) = equiangular::sample(&s.world, s.light, s.a, s.b, rng.next_f32());
                if pdf0 > 0.0 && pdf0.is_finite() {
                    let mu_w = Self::mu(v, s, t0, rng, lookups);
                    let mu = if v.needs_jitter() {
                        Self::mu(v, s, t0, rng, lookups)
                    } else {
                        mu_w
                    };
                    if mu > 0.0 {
                        let (x0, x1) = self.depths(v, s, t0, false, rng, lookups);
                        let (mw, p) = (mu_w as f64, pdf0 as f64);
                        let w0 = mis_weight(0.0, p, mw, p, x0, x1) as f32;
                        let tr = ratio_tracking::transmittance(v, &s.index, s.a, t0, rng);
                        *lookups += tr.lookups;
                        let c = w0 * tr.transmittance * mu / pdf0;
                        if c != 0.0 && c.is_finite() {
                            total += self.in_scattered(s, t0, rng, lookups) * c;
                        }
                    }
                }
            }
            Strategy::MisNaive | Strategy::MisJackknifeBiased => {
                // Seed 000, Eq. 10: both samples contribute g̃(τ(t_j)) L_s(t_j)
                // with g(τ) = μ e^{−τ}/(p0 + μ e^{−τ}) (Eq. 11), estimated by
                // Eq. 12 (jackknife) or g(X) (naive, m = 1).
                let naive = self.strategy == Strategy::MisNaive;
                let f = delta_tracking_ratio::sample(v, &s.index, s.a, s.b, rng);
                *lookups += f.lookups;
                let (t0, pdf0) = equiangular::sample(&s.world, s.light, s.a, s.b, rng.next_f32());
                let mut ts = [None, None];
                if let Some(t1) = f.t {
                    ts[0] = Some((t1, p0(t1), Some(f.mu)));
                }
                if pdf0 > 0.0 && pdf0.is_finite() {
                    ts[1] = Some((t0, pdf0, None));
                }
                for (t, p, known_mu) in ts.into_iter().flatten() {
                    let mu = match known_mu {
                        Some(m) if !v.needs_jitter() => m,
                        _ => Self::mu(v, s, t, rng, lookups),
                    };
                    if mu <= 0.0 {
                        continue;
                    }
                    let (x0, x1) = self.depths(v, s, t, naive, rng, lookups);
                    let m = mu as f64;
                    let g = mis_weight(m, 0.0, m, p as f64, x0, x1) as f32;
                    if g != 0.0 && g.is_finite() {
                        total += self.in_scattered(s, t, rng, lookups) * g;
                    }
                }
            }
        }
        total
    }
}

/// [`PointMis::depths`] with an explicit N.
fn depths_n<V: VolumeAccess>(
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
    optical_depths(
        v,
        &s.index,
        s.a,
        t,
        n,
        StepMode::FixedCount,
        Importance::VarianceAware,
        Jitter::Stratified,
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

impl PointMis {
    /// Seed 000 Fig. 13 in isolation: one pixel sample of Eq. 10 with exact
    /// weights g(τ(t_j)) and the errors of its estimated weights, on common
    /// random numbers.
    ///
    /// The light choice, the distances t0, t1, μ(t_j) and one estimate
    /// L̃_s(t_j) per distance are drawn exactly as [`Strategy::MisNaive`] and
    /// [`Strategy::MisJackknifeBiased`] draw them; τ(t_j) is computed exactly
    /// by regular tracking. Returns Σ_j g(τ(t_j)) L̃_s(t_j) / P(light), an
    /// unbiased estimate of the single-scattering radiance (Eq. 10 with exact
    /// weights is the balance heuristic), and writes to `errors[k]`
    /// [naive, jackknife] = Σ_j (g̃(t_j) − g(τ(t_j))) L̃_s(t_j) / P(light)
    /// for N = `mis_samples[k]`, each g̃ from its own optical-depth estimates
    /// (independent of L̃_s, as in the integrator). So E[errors[k][0]] is
    /// exactly the bias of `mis_naive` with `integrator.mis_samples = N`,
    /// and likewise for `mis_jackknife_biased`, but with far less variance
    /// than a difference of two renders. `None` where τ cannot be computed
    /// exactly (filters other than nearest on grids).
    pub fn eq10_weight_errors(
        &self,
        scene: &Scene,
        x: u32,
        y: u32,
        key: SampleKey,
        mis_samples: &[u32],
        errors: &mut [[Vec3; 2]],
    ) -> Option<Vec3> {
        errors.iter_mut().for_each(|e| *e = [Vec3::ZERO; 2]);
        let medium = scene.media.first()?;
        let view = medium.medium.view();
        if !matches!(view, MediumView::Analytic(_)) && medium.medium.filter != Filter::Nearest {
            return None;
        }
        let mut rng = SampleKey {
            dimension: dim::ESTIMATOR,
            ..key
        }
        .rng();
        let world = primary_ray(scene, x, y, key);
        let Some((index, a, b)) = medium.medium.to_index(&world, 0.0, f32::INFINITY) else {
            return Some(Vec3::ZERO);
        };
        let Some((li, pmf)) = self.lights.pick(rng.next_f32()) else {
            return Some(Vec3::ZERO);
        };
        let Light::Point {
            position,
            intensity,
        } = scene.lights[li]
        else {
            return Some(Vec3::ZERO);
        };
        if pmf <= 0.0 {
            return Some(Vec3::ZERO);
        }
        let seg = Segment {
            medium,
            world,
            index,
            a,
            b,
            light: position,
            intensity,
            hg: HenyeyGreenstein { g: medium.phase_g },
        };
        let l = match view {
            MediumView::F16(v) => self.eq10_errors_in(&v, &seg, mis_samples, errors, &mut rng),
            MediumView::F32(v) => self.eq10_errors_in(&v, &seg, mis_samples, errors, &mut rng),
            MediumView::Analytic(v) => self.eq10_errors_in(&v, &seg, mis_samples, errors, &mut rng),
        };
        errors
            .iter_mut()
            .for_each(|e| *e = [e[0] / pmf, e[1] / pmf]);
        Some(l / pmf)
    }

    fn eq10_errors_in<V: VolumeAccess>(
        &self,
        v: &V,
        s: &Segment,
        mis_samples: &[u32],
        errors: &mut [[Vec3; 2]],
        rng: &mut Pcg32,
    ) -> Vec3 {
        let mut lookups = 0u32;
        let p0 = |t: f32| equiangular::pdf(&s.world, s.light, s.a, s.b, t);
        // The same draws, in the same order, as the Eq. 10 strategies.
        let f = delta_tracking_ratio::sample(v, &s.index, s.a, s.b, rng);
        let (t0, pdf0) = equiangular::sample(&s.world, s.light, s.a, s.b, rng.next_f32());
        let mut ts = [None, None];
        if let Some(t1) = f.t {
            ts[0] = Some((t1, p0(t1), Some(f.mu)));
        }
        if pdf0 > 0.0 && pdf0.is_finite() {
            ts[1] = Some((t0, pdf0, None));
        }
        let mut total = Vec3::ZERO;
        for (t, p, known_mu) in ts.into_iter().flatten() {
            let mu = match known_mu {
                Some(m) if !v.needs_jitter() => m,
                _ => Self::mu(v, s, t, rng, &mut lookups),
            };
            if mu <= 0.0 {
                continue;
            }
            let ls = self.in_scattered(s, t, rng, &mut lookups);
            let tr = transmittance(
                Estimator::RegularTracking,
                &s.medium.medium,
                &s.world,
                t,
                rng,
            )
            .transmittance as f64;
            let (m, p) = (mu as f64, p as f64);
            let g = balance_f64(m * tr, p);
            total += ls * g as f32;
            for (&n, e) in mis_samples.iter().zip(errors.iter_mut()) {
                for (k, naive) in [(0, true), (1, false)] {
                    let (x0, x1) = depths_n(v, s, t, n, naive, rng, &mut lookups);
                    let gk = mis_weight(m, 0.0, m, p, x0, x1);
                    if gk.is_finite() {
                        e[k] += ls * (gk - g) as f32;
                    }
                }
            }
        }
        total
    }
}

fn balance_f64(q: f64, p: f64) -> f64 {
    let d = q + p;
    if d > 0.0 && d.is_finite() {
        q / d
    } else {
        0.0
    }
}

/// Seed 000 App. D in isolation: the jackknife estimates of w0(t) and w1(t)
/// at a point t of the camera ray `world`, each from its own pair of
/// optical-depth estimates of [entry, t], as [`Strategy::MisJackknife`]
/// computes them. `p0` is the other strategy's density at t. Returns
/// (w̃0, w̃1, lookups); E[w̃0] + E[w̃1] = 1 although neither sum is 1.
pub fn jackknife_weights(
    medium: &SceneMedium,
    world: &Ray,
    t: f32,
    p0: f32,
    mis_samples: u32,
    rng: &mut Pcg32,
) -> Option<(f64, f64, u32)> {
    let (index, a, _) = medium.medium.to_index(world, 0.0, f32::INFINITY)?;
    let mut lookups = 0u32;
    let pm = PointMis {
        strategy: Strategy::MisJackknife,
        nee: Estimator::RatioTracking,
        mis_samples,
        lights: LightSampler::default(),
    };
    let seg = Segment {
        medium,
        world: *world,
        index,
        a,
        b: t,
        light: Vec3::ZERO,
        intensity: Vec3::ZERO,
        hg: HenyeyGreenstein { g: 0.0 },
    };
    let (w0, w1) = match medium.medium.view() {
        MediumView::F16(v) => weights_pair(&pm, &v, &seg, t, p0, rng, &mut lookups),
        MediumView::F32(v) => weights_pair(&pm, &v, &seg, t, p0, rng, &mut lookups),
        MediumView::Analytic(v) => weights_pair(&pm, &v, &seg, t, p0, rng, &mut lookups),
    };
    Some((w0, w1, lookups))
}

fn weights_pair<V: VolumeAccess>(
    pm: &PointMis,
    v: &V,
    s: &Segment,
    t: f32,
    p0: f32,
    rng: &mut Pcg32,
    lookups: &mut u32,
) -> (f64, f64) {
    let p = p0 as f64;
    let mu0 = PointMis::mu(v, s, t, rng, lookups) as f64;
    let (a0, a1) = pm.depths(v, s, t, false, rng, lookups);
    let w0 = mis_weight(0.0, p, mu0, p, a0, a1);
    let mu1 = PointMis::mu(v, s, t, rng, lookups) as f64;
    let (b0, b1) = pm.depths(v, s, t, false, rng, lookups);
    let w1 = mis_weight(mu1, 0.0, mu1, p, b0, b1);
    (w0, w1)
}

//! Analyses of the MIS weights behind `point_mis`, on common random
//! numbers: the errors of Eq. 10's estimated weights against exact ones
//! (Peters 2025 Fig. 13) and the jackknife weights of Eq. 9 at one point
//! (App. D).

use super::integrator::{depths_n, eq10_distances, PointMis, Segment};
use super::strategy::Strategy;
use crate::integrators::shared::context::PathContext;
use crate::integrators::shared::{balance, estimator_rng};
use crate::lights::sample::LightSampler;
use crate::world::medium::SceneMedium;
use crate::world::phase::HenyeyGreenstein;
use crate::world::World;
use fogbank_estimators::estimator::{RatioTracking, RegularTracking};
use fogbank_estimators::jackknife_function::mis_weight;
use fogbank_estimators::{transmittance, Estimator};
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};
use fogbank_volume::{Filter, MediumView, VolumeAccess};

impl PointMis {
    /// Peters 2025 Fig. 13 in isolation: one pixel sample of Eq. 10 with exact
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
        world: &World,
        x: u32,
        y: u32,
        key: SampleKey,
        mis_samples: &[u32],
        errors: &mut [[Vec3; 2]],
    ) -> Option<Vec3> {
        errors.iter_mut().for_each(|e| *e = [Vec3::ZERO; 2]);
        let medium = world.media.first()?;
        let view = medium.medium.view();
        if !matches!(view, MediumView::Analytic(_)) && medium.medium.filter != Filter::Nearest {
            return None;
        }
        let mut rng = estimator_rng(key);
        let Some((seg, pmf)) = self.begin(world, x, y, key, &mut rng) else {
            return Some(Vec3::ZERO);
        };
        let cx = &mut PathContext::new(world, &mut rng);
        let l = match view {
            MediumView::F16(v) => self.eq10_errors_in(&v, &seg, mis_samples, errors, cx),
            MediumView::F32(v) => self.eq10_errors_in(&v, &seg, mis_samples, errors, cx),
            MediumView::Analytic(v) => self.eq10_errors_in(&v, &seg, mis_samples, errors, cx),
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
        cx: &mut PathContext,
    ) -> Vec3 {
        // The same draws, in the same order, as the Eq. 10 strategies.
        let ts = eq10_distances(v, s, cx.rng, &mut 0);
        let mut total = Vec3::ZERO;
        for (t, p, known_mu) in ts.into_iter().flatten() {
            let sigma_t = Self::collision_sigma_t(v, s, t, known_mu, cx);
            if sigma_t <= 0.0 {
                continue;
            }
            let ls = self.in_scattered(s, t, cx);
            let tr = transmittance(
                Estimator::RegularTracking(RegularTracking),
                &s.medium.medium,
                &s.world,
                t,
                cx.rng,
            )
            .transmittance as f64;
            let (m, p) = (sigma_t as f64, p as f64);
            let g = balance(m * tr, p);
            total += ls * g as f32;
            for (&n, e) in mis_samples.iter().zip(errors.iter_mut()) {
                for (k, naive) in [(0, true), (1, false)] {
                    let (x0, x1) = depths_n(v, s, t, n, naive, cx.rng, &mut cx.lookups);
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

/// Peters 2025 App. D in isolation: the jackknife estimates of w0(t) and w1(t)
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
        nee: Estimator::RatioTracking(RatioTracking { roulette: 0.0 }),
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
        surfaces: None,
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
    let sigma_t0 = PointMis::segment_sigma_t(v, s, t, rng, lookups) as f64;
    let (a0, a1) = pm.depths(v, s, t, false, rng, lookups);
    let w0 = mis_weight(0.0, p, sigma_t0, p, a0, a1);
    let sigma_t1 = PointMis::segment_sigma_t(v, s, t, rng, lookups) as f64;
    let (b0, b1) = pm.depths(v, s, t, false, rng, lookups);
    let w1 = mis_weight(sigma_t1, 0.0, sigma_t1, p, b0, b1);
    (w0, w1)
}

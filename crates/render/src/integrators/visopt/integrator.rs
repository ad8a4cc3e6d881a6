//! `visopt`: Monte Carlo volume visualisation with the visibility of
//! important regions optimised per view (Lerzer and Dachsbacher 2025 §5.4). Delta tracking
//! with μ' (Eq. 8) on camera rays samples a real collision; its emission
//! and next-event estimation toward one light (ratio tracking, with μ' of a
//! fresh light-ray list when `light_samples > 0`) give the pixel; HG plus
//! the gradient lobe is the phase function at NEE. With `scattering` =
//! first or all, the path continues by HG sampling through the original μ
//! (scatter-to-scatter segments are never optimised), with NEE at every
//! vertex, optimised only with `all`. Light sampling is the only strategy
//! toward lights (the lobe has no sampling routine), so escaping paths add
//! nothing. Shapes are opaque black occluders (`shared/occluders.rs`).

use super::lists::{light_list, CameraLists};
use super::optimised::{Optimised, RayList, Weights};
use super::params::{Scattering, VisOptParams};
use super::segments::Segment;
use crate::error::SceneError;
use crate::integrators::plugin::Integrator;
use crate::integrators::shared::context::PathContext;
use crate::integrators::shared::free_flight::next_collision;
use crate::integrators::shared::next_event::escaped;
use crate::integrators::shared::{
    estimator_rng, occluders, primary_ray, DistanceSampler, PixelSample,
};
use crate::lights::sample::{LightSampler, Vertex};
use crate::world::medium::SceneMedium;
use crate::world::shading::dvr_phase;
use crate::world::World;
use fogbank_estimators::distance::delta_tracking;
use fogbank_estimators::ratio_tracking;
use fogbank_estimators::Estimator;
use fogbank_math::{Ray, RaySegment, SampleKey, Vec3};
use fogbank_volume::MediumView;
use std::sync::{Arc, OnceLock};

/// Expands `body` once per storage type with `v` bound to the typed view, so
/// the tracking loops are monomorphised and the match happens once per ray.
macro_rules! with_view {
    ($m:expr, $v:ident => $body:expr) => {
        match $m.medium.view() {
            MediumView::F16($v) => $body,
            MediumView::F32($v) => $body,
            MediumView::Analytic($v) => $body,
        }
    };
}

thread_local! {
    /// Scratch for one NEE ray's importance list (no allocation per sample).
    static LIGHT_LIST: std::cell::RefCell<Vec<Segment>> = const { std::cell::RefCell::new(Vec::new()) };
}

#[derive(Clone, Debug)]
pub struct VisOpt {
    pub params: VisOptParams,
    pub lights: LightSampler,
    /// 2 / the medium's longest world extent: world lengths → [−1, 1]³.
    pub unit: f32,
    lists: Arc<OnceLock<CameraLists>>,
}

impl VisOpt {
    pub fn new(p: &VisOptParams, world: &World) -> Result<VisOpt, SceneError> {
        if world.media.len() != 1 {
            return Err(SceneError(format!(
                "integrator \"visopt\" renders scenes with exactly one medium (this one has {})",
                world.media.len()
            )));
        }
        occluders::check(world, "visopt")?;
        let b = world.media[0].medium.world_bounds();
        let extent = (b.max - b.min).max_element();
        if !(extent > 0.0 && extent.is_finite()) {
            return Err(SceneError(
                "integrator \"visopt\": the medium has no extent".into(),
            ));
        }
        Ok(VisOpt {
            params: p.clone(),
            lights: LightSampler::new(&world.lights, world.radius(), world.light_selection),
            unit: 2.0 / extent,
            lists: Arc::new(OnceLock::new()),
        })
    }

    /// The frozen camera lists (built on first use).
    pub fn lists(&self, world: &World) -> &CameraLists {
        self.lists
            .get_or_init(|| CameraLists::build(world, &self.params, self.unit, 0))
    }

    pub(crate) fn weights(&self) -> Weights {
        let p = &self.params;
        Weights {
            p: p.p,
            q: p.q,
            r: p.r,
            lambda: p.lambda,
        }
    }

    /// Multiple scattering after the first vertex (§5.4 settings 2 and 3):
    /// HG-sampled directions, free flights through the original μ.
    fn continue_path(
        &self,
        cx: &mut PathContext,
        m: &SceneMedium,
        mut p: Vec3,
        mut d: Vec3,
    ) -> Vec3 {
        let world = cx.world;
        let hg = m.phase;
        let optimise_nee = self.params.optimise && self.params.scattering == Scattering::All;
        let (mut beta, mut radiance) = (Vec3::ONE, Vec3::ZERO);
        for depth in 1..self.params.max_depth {
            let (wi, _) = hg.sample(-d, cx.next_2d());
            let ray = Ray::new(p, wi);
            let t_end = occluders::first_surface(world, &ray);
            let delta_tracking = DistanceSampler::DeltaTracking.into();
            let Some((t, _)) = next_collision(cx, delta_tracking, &ray, t_end, None) else {
                break;
            };
            p = ray.at(t);
            d = wi;
            let albedo = m.albedo_at(p);
            radiance += beta * m.emitted(p, albedo);
            beta *= albedo;
            if beta == Vec3::ZERO {
                break;
            }
            radiance += beta * self.next_event(cx, p, d, optimise_nee);
            if depth >= 3 {
                let q = beta.max_element().min(1.0);
                if cx.next_f32() >= q {
                    break;
                }
                beta /= q;
            }
        }
        radiance
    }

    /// L_i f T / pdf toward one light picked by power, f = HG + lobe, T by
    /// ratio tracking through μ' of a fresh light-ray list (`optimise`) or
    /// through μ.
    fn next_event(&self, cx: &mut PathContext, p: Vec3, d: Vec3, optimise: bool) -> Vec3 {
        let world = cx.world;
        let m = &world.media[0];
        let Some((li, pmf)) = self.lights.pick(cx.next_f32(), Vertex::Medium, p) else {
            return Vec3::ZERO;
        };
        let Some(ls) = world.lights[li].sample_li(p, cx.next_2d()) else {
            return Vec3::ZERO;
        };
        let f = self.phase(m, p, d, ls.wi);
        if f <= 0.0 || ls.radiance == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let shadow = Ray::new(p, ls.wi);
        if !occluders::visible(world, &shadow, ls.distance) {
            return Vec3::ZERO;
        }
        let rng = &mut *cx.rng;
        let tr = match m.medium.to_index(&shadow, 0.0, ls.distance) {
            None => 1.0,
            Some((r, s0, s1)) => {
                let est = if optimise && self.params.light_samples > 0 {
                    // The NEE ray's list lives in per-thread scratch.
                    LIGHT_LIST.with_borrow_mut(|scratch| {
                        let (big_k_z, length) =
                            light_list(m, &shadow, (s0, s1), &self.params, self.unit, rng, scratch);
                        let list = RayList {
                            list: scratch,
                            big_k_z,
                            length,
                            origin: s1,
                            sign: -1.0,
                        };
                        with_view!(m, v => {
                            let o = Optimised { inner: &v, medium: m, ray: r, list, weights: self.weights(), unit: self.unit };
                            ratio_tracking::transmittance(&o, &RaySegment::new(r, s0, s1), rng, 0.0)
                        })
                    })
                } else {
                    with_view!(m, v => ratio_tracking::transmittance(&v, &RaySegment::new(r, s0, s1), rng, 0.0))
                };
                cx.lookups += est.lookups;
                est.transmittance
            }
        };
        ls.radiance * (f * tr / (pmf * if ls.is_delta { 1.0 } else { ls.pdf }))
    }

    /// HG plus, with `shading`, the gradient lobe in normalised units.
    pub fn phase(&self, m: &SceneMedium, p: Vec3, d: Vec3, wi: Vec3) -> f32 {
        let lobe = self.params.shading.then_some(self.params.n);
        dvr_phase(m, p, d, wi, lobe, self.unit)
    }
}

impl Integrator for VisOpt {
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let mut rng = estimator_rng(key);
        let cx = &mut PathContext::new(world, &mut rng);
        let ray = primary_ray(world, x, y, key);
        let m = &world.media[0];
        let t_end = occluders::first_surface(world, &ray);
        // The environment, unless a surface hides it (black: occluders.rs).
        let background = || match t_end {
            f32::INFINITY => escaped(world, &self.lights, ray.d, None),
            _ => Vec3::ZERO,
        };
        let Some((r, t0, t1)) = m.medium.to_index(&ray, 0.0, t_end) else {
            return PixelSample {
                radiance: background(),
                lookups: 0,
            };
        };
        let list = self.lists(world).ray_list(x, y, t0);
        let flight = if self.params.optimise {
            with_view!(m, v => {
                let o = Optimised { inner: &v, medium: m, ray: r, list, weights: self.weights(), unit: self.unit };
                delta_tracking::sample(&o, &RaySegment::new(r, t0, t1), cx.rng)
            })
        } else {
            with_view!(m, v => delta_tracking::sample(&v, &RaySegment::new(r, t0, t1), cx.rng))
        };
        cx.lookups += flight.lookups;
        let Some(t) = flight.t else {
            return PixelSample {
                radiance: background(),
                lookups: cx.lookups,
            };
        };
        let p = ray.at(t);
        let albedo = m.albedo_at(p);
        let mut radiance = m.emitted(p, albedo);
        radiance += albedo * self.next_event(cx, p, ray.d, self.params.optimise);
        if self.params.scattering != Scattering::Single {
            radiance += albedo * self.continue_path(cx, m, p, ray.d);
        }
        PixelSample {
            radiance,
            lookups: cx.lookups,
        }
    }

    /// Its shadow rays are ratio tracking by construction.
    fn estimator(&self) -> Option<Estimator> {
        None
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        None
    }

    fn prepare(&self, world: &World) {
        self.lists(world);
    }

    fn occluders_only(&self) -> bool {
        true
    }
}

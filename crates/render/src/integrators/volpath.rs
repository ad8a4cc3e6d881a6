//! `volpath`: multiple scattering with next-event estimation at every vertex.
//!
//! Free-flight distance sampling picks the next real collision across all
//! media (the first collision of independent processes whose extinctions
//! add); the path throughput gains the scattering medium's albedo. At every
//! vertex one light is chosen by power and its contribution is weighted by
//! the NEE transmittance estimate; environment lights combine light and
//! phase sampling with the balance heuristic. Russian roulette on the
//! throughput after `rr_depth` bounces (seed 002 uses 3).

use super::{dim, primary_ray, PixelSample};
use crate::lights::sample::LightSampler;
use crate::phase::HenyeyGreenstein;
use crate::scene::Scene;
use fogbank_estimators::distance::{
    decomposition_tracking, delta_tracking, regular_tracking, FreeFlight,
};
use fogbank_estimators::{transmittance, Estimator};
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};
use fogbank_volume::MediumView;

/// Free-flight distance sampler of `volpath`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DistanceSampler {
    DeltaTracking,
    DecompositionTracking,
    /// Exact for nearest-filtered grids; analytic media fall back to delta tracking.
    RegularTracking,
}

impl DistanceSampler {
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

#[derive(Clone, Debug)]
pub struct VolPath {
    pub distance: DistanceSampler,
    pub nee: Estimator,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub lights: LightSampler,
}

fn free_flight(
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

fn balance(a: f32, b: f32) -> f32 {
    if a + b > 0.0 {
        a / (a + b)
    } else {
        0.0
    }
}

impl VolPath {
    fn shadow(
        &self,
        scene: &Scene,
        ray: &Ray,
        distance: f32,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> f32 {
        let mut t = 1.0;
        for m in &scene.media {
            let e = transmittance(self.nee, &m.medium, ray, distance, rng);
            *lookups += e.lookups;
            t *= e.transmittance;
        }
        t
    }

    pub fn sample(&self, scene: &Scene, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let mut rng = SampleKey {
            dimension: dim::ESTIMATOR,
            ..key
        }
        .rng();
        let mut ray = primary_ray(scene, x, y, key);
        let (mut beta, mut radiance, mut lookups) = (Vec3::ONE, Vec3::ZERO, 0u32);
        let mut phase_pdf: Option<f32> = None;
        for depth in 0..self.max_depth {
            // Next real collision across all media.
            let mut hit: Option<(f32, usize)> = None;
            for (i, m) in scene.media.iter().enumerate() {
                let t_max = hit.map_or(f32::INFINITY, |h| h.0);
                let f = free_flight(self.distance, &m.medium, &ray, t_max, &mut rng);
                lookups += f.lookups;
                if let Some(t) = f.t {
                    hit = Some((t, i));
                }
            }
            let Some((t, mi)) = hit else {
                // Escaped: environment lights, MIS-weighted against NEE after a scattering.
                for (li, l) in scene
                    .lights
                    .iter()
                    .enumerate()
                    .filter(|(_, l)| l.is_environment())
                {
                    let le = l.le(ray.d);
                    let w = phase_pdf
                        .map_or(1.0, |p| balance(p, self.lights.pmf(li) * l.pdf_li(ray.d)));
                    radiance += beta * le * w;
                }
                break;
            };
            let m = &scene.media[mi];
            let p = ray.at(t);
            beta *= Vec3::from(m.albedo);
            let hg = HenyeyGreenstein { g: m.phase_g };
            // Next-event estimation.
            if let Some((li, pmf)) = self.lights.pick(rng.next_f32()) {
                let light = &scene.lights[li];
                if let Some(ls) = light.sample_li(p, [rng.next_f32(), rng.next_f32()]) {
                    let f = hg.eval(ray.d.dot(ls.wi));
                    if f > 0.0 && ls.radiance != Vec3::ZERO {
                        let tr = self.shadow(
                            scene,
                            &Ray::new(p, ls.wi),
                            ls.distance,
                            &mut rng,
                            &mut lookups,
                        );
                        if ls.is_delta {
                            radiance += beta * ls.radiance * (f * tr / pmf);
                        } else {
                            let light_pdf = pmf * ls.pdf;
                            radiance +=
                                beta * ls.radiance * (f * tr * balance(light_pdf, f) / light_pdf);
                        }
                    }
                }
            }
            // Phase sampling; HG sampling is exact, so f/pdf = 1.
            let (wi, pdf) = hg.sample(-ray.d, [rng.next_f32(), rng.next_f32()]);
            phase_pdf = Some(pdf);
            ray = Ray::new(p, wi);
            if depth + 1 >= self.rr_depth {
                let q = beta.max_element().min(1.0);
                if rng.next_f32() >= q {
                    break;
                }
                beta /= q;
            }
        }
        PixelSample { radiance, lookups }
    }
}

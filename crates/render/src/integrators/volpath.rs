//! `volpath`: multiple scattering with next-event estimation at every vertex.
//!
//! Free-flight distance sampling picks the next real collision across all
//! media (the first collision of independent processes whose extinctions
//! add); the path throughput gains the scattering medium's albedo. At every
//! vertex one light is chosen by power and its contribution is weighted by
//! the NEE transmittance estimate; environment lights combine light and
//! phase sampling with the balance heuristic; at the last vertex
//! (`max_depth`) the phase-sampled partner is evaluated with the NEE
//! estimator instead of being traced, so no MIS weight is left without its
//! partner. A real collision adds the medium's emission (σ_a/σ_t) L_e.
//! Russian roulette on the throughput after `rr_depth` bounces (seed 002
//! uses 3).

use super::media::next_collision;
use super::next_event::{escaped, light_sample, phase_sample_to_environment};
use super::{dim, primary_ray, PixelSample};
use crate::lights::sample::LightSampler;
use crate::phase::HenyeyGreenstein;
use crate::scene::Scene;
use fogbank_estimators::Estimator;
use fogbank_math::{Ray, SampleKey, Vec3};

pub use super::media::DistanceSampler;

#[derive(Clone, Debug)]
pub struct VolPath {
    pub distance: DistanceSampler,
    pub nee: Estimator,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub lights: LightSampler,
}

impl VolPath {
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
            let Some((t, mi)) = next_collision(self.distance, scene, &ray, &mut rng, &mut lookups)
            else {
                radiance += beta * escaped(scene, &self.lights, ray.d, phase_pdf);
                break;
            };
            let m = &scene.media[mi];
            let p = ray.at(t);
            let albedo = m.albedo_at(p);
            radiance += beta * m.emitted(p, albedo);
            beta *= albedo;
            if beta == Vec3::ZERO {
                break;
            }
            let hg = HenyeyGreenstein { g: m.phase_g };
            radiance += beta
                * light_sample(
                    scene,
                    &self.lights,
                    self.nee,
                    p,
                    ray.d,
                    &hg,
                    &mut rng,
                    &mut lookups,
                );
            let (wi, pdf) = hg.sample(-ray.d, [rng.next_f32(), rng.next_f32()]);
            if depth + 1 == self.max_depth {
                radiance += beta
                    * phase_sample_to_environment(
                        scene,
                        &self.lights,
                        self.nee,
                        p,
                        wi,
                        pdf,
                        &mut rng,
                        &mut lookups,
                    );
                break;
            }
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

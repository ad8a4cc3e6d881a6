//! `direct`: single scattering. The camera ray's first real collision
//! (free-flight sampling with the configured distance sampler) gathers the
//! medium's emission and the light of every source: light sampling toward
//! one light chosen by power, MIS-combined with phase sampling for
//! environments, each shadow ray's transmittance estimated by the NEE
//! estimator. This is the setting of seed 000 Fig. 1 (a cloud under a light
//! probe, estimators compared at equal spp), where the NEE estimator is the
//! only thing that changes. It equals `volpath` with `max_depth = 1`.

use super::media::{next_collision, DistanceSampler};
use super::next_event::{escaped, light_sample, phase_sample_to_environment};
use super::{dim, primary_ray, PixelSample};
use crate::lights::sample::LightSampler;
use crate::phase::HenyeyGreenstein;
use crate::scene::Scene;
use fogbank_estimators::Estimator;
use fogbank_math::{SampleKey, Vec3};

#[derive(Clone, Debug)]
pub struct Direct {
    pub distance: DistanceSampler,
    pub nee: Estimator,
    pub lights: LightSampler,
}

impl Direct {
    pub fn sample(&self, scene: &Scene, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let mut rng = SampleKey {
            dimension: dim::ESTIMATOR,
            ..key
        }
        .rng();
        let ray = primary_ray(scene, x, y, key);
        let mut lookups = 0u32;
        let Some((t, mi)) = next_collision(self.distance, scene, &ray, &mut rng, &mut lookups)
        else {
            return PixelSample {
                radiance: escaped(scene, &self.lights, ray.d, None),
                lookups,
            };
        };
        let m = &scene.media[mi];
        let p = ray.at(t);
        let albedo = m.albedo_at(p);
        let mut radiance = m.emitted(p, albedo);
        if albedo != Vec3::ZERO {
            let hg = HenyeyGreenstein { g: m.phase_g };
            let (lights, nee) = (&self.lights, self.nee);
            let rng = &mut rng;
            radiance += albedo * light_sample(scene, lights, nee, p, ray.d, &hg, rng, &mut lookups);
            let (wi, pdf) = hg.sample(-ray.d, [rng.next_f32(), rng.next_f32()]);
            radiance += albedo
                * phase_sample_to_environment(scene, lights, nee, p, wi, pdf, rng, &mut lookups);
        }
        PixelSample { radiance, lookups }
    }
}

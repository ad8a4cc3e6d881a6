//! The transmittance view of seed 000 §6.1: per pixel, the transmittance of
//! the primary ray through all media in front of a uniform background, so
//! the image is T itself. Overlapping media add extinctions, hence multiply
//! transmittances; independent unbiased estimates multiply to an unbiased
//! estimate.

use super::{dim, PixelSample};
use crate::scene::Scene;
use fogbank_estimators::{transmittance, Estimate, Estimator};
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};

/// Transmittance of all media along `ray` (to infinity).
pub fn along_ray(scene: &Scene, estimator: Estimator, ray: &Ray, rng: &mut Pcg32) -> Estimate {
    let mut total = Estimate::ONE;
    for m in &scene.media {
        let e = transmittance(estimator, &m.medium, ray, f32::INFINITY, rng);
        total.transmittance *= e.transmittance;
        total.lookups += e.lookups;
    }
    total
}

pub fn sample(
    scene: &Scene,
    estimator: Estimator,
    background: Vec3,
    x: u32,
    y: u32,
    key: SampleKey,
) -> PixelSample {
    let ray = super::primary_ray(scene, x, y, key);
    let mut rng = SampleKey {
        dimension: dim::ESTIMATOR,
        ..key
    }
    .rng();
    let e = along_ray(scene, estimator, &ray, &mut rng);
    PixelSample {
        radiance: background * e.transmittance,
        lookups: e.lookups,
    }
}

//! `transmittance`: the transmittance view of Peters 2025 §6.1. Per pixel, the
//! transmittance of the primary ray through all media in front of a uniform
//! background, so the image is T itself. Overlapping media add extinctions,
//! hence multiply transmittances; independent unbiased estimates multiply to
//! an unbiased estimate.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `estimator` | ratio_tracking (roulette 0.03) | transmittance estimator (`fogbank estimators`), with its options flat in `[integrator]` or as `{ type = "…", … }` |
//! | `background` | [1, 1, 1] | radiance behind the media; the image is T · background |

use super::shared::context::PathContext;
use super::shared::free_flight::{shadow_transmittance_in, ShadowSpan};
use super::shared::tracking::Shadow;
use super::shared::{estimator_rng, primary_ray, PixelSample};
use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, Integrator, IntegratorParams};
use crate::params::{estimator_value, take_estimator, Param, ParamReader};
use crate::world::World;
use fogbank_estimators::{transmittance, Estimate, Estimator};
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};

pub const PARAMS: [Param; 2] = [
    Param {
        key: "estimator",
        default: "ratio_tracking (roulette 0.03)",
        meaning: "transmittance estimator (`fogbank estimators`), with its options flat in `[integrator]` or as `{ type = \"…\", … }`",
    },
    Param {
        key: "background",
        default: "[1, 1, 1]",
        meaning: "radiance behind the media; the image is T · background",
    },
];

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransmittanceParams {
    pub estimator: Estimator,
    pub background: [f32; 3],
}

impl Default for TransmittanceParams {
    fn default() -> Self {
        TransmittanceParams {
            estimator: Estimator::default(),
            background: [1.0; 3],
        }
    }
}

impl IntegratorParams for TransmittanceParams {
    const NAME: &'static str = "transmittance";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: true,
        far_clip: true,
    };

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let d = TransmittanceParams::default();
        Ok(TransmittanceParams {
            estimator: take_estimator(r)?,
            background: r.take("background")?.unwrap_or(d.background),
        })
    }

    fn write(&self, t: &mut toml::Table) {
        t.insert("estimator".into(), estimator_value(self.estimator));
        let bg = self.background.map(|c| toml::Value::from(f64::from(c)));
        t.insert("background".into(), toml::Value::Array(bg.to_vec()));
    }

    fn estimator(&self) -> Estimator {
        self.estimator
    }
}

/// Transmittance of all media along `ray` (to infinity).
pub fn along_ray(
    world: &World,
    estimator: Estimator,
    ray: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> Estimate {
    let mut total = Estimate::ONE;
    for m in &world.media {
        let e = transmittance(estimator, &m.medium, ray, t_max, rng);
        total.transmittance *= e.transmittance;
        total.lookups += e.lookups;
    }
    total
}

/// The built integrator: the transmittance of each camera ray by
/// `estimator`, times a constant `background`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transmittance {
    pub estimator: Estimator,
    pub background: Vec3,
}

impl Integrator for Transmittance {
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        sample(world, self.estimator, self.background, x, y, key)
    }

    fn estimator(&self) -> Option<Estimator> {
        Some(self.estimator)
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        Some(&mut self.estimator)
    }
}

fn sample(
    world: &World,
    estimator: Estimator,
    background: Vec3,
    x: u32,
    y: u32,
    key: SampleKey,
) -> PixelSample {
    let ray = primary_ray(world, x, y, key);
    let t_max = world.camera.ray_end(&ray);
    let mut rng = estimator_rng(key);
    let chromatic = world.media.iter().any(|m| m.chroma.is_some());
    if world.surfaces.is_some() || chromatic {
        // Surfaces hide the background (null boundaries and thin
        // dielectrics let part of it through), bounded media count only
        // inside their shapes, and chromatic media per channel.
        let camera_medium = world.surfaces.as_ref().and_then(|s| s.camera_medium);
        let cx = &mut PathContext::new(world, &mut rng);
        let nee = Shadow::Estimator(estimator);
        let t = shadow_transmittance_in(cx, nee, ShadowSpan::new(ray, t_max, camera_medium));
        return PixelSample {
            radiance: background * t,
            lookups: cx.lookups,
        };
    }
    let e = along_ray(world, estimator, &ray, t_max, &mut rng);
    PixelSample {
        radiance: background * e.transmittance,
        lookups: e.lookups,
    }
}

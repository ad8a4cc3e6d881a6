//! `direct`: single scattering. The camera ray's first real collision
//! (free-flight sampling with the configured distance sampler) gathers the
//! medium's emission and the light of every source: light sampling toward
//! one light chosen by power, MIS-combined with phase sampling for
//! environments, each shadow ray's transmittance estimated by the NEE
//! estimator. This is the setting of Peters 2025 Fig. 1 (a cloud under a light
//! probe, estimators compared at equal spp), where the NEE estimator is the
//! only thing that changes. It equals `volpath` with `max_depth = 1`.

//!
//! Parameters (those `volpath` shares, [`ScatterParams`]):
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `distance_sampler` | delta_tracking | free-flight sampler: `delta_tracking`, `decomposition_tracking`, `regular_tracking` |
//! | `estimator` | ratio_tracking (roulette 0.03) | NEE transmittance estimator (`fogbank estimators`), with its options |
//! | `preset` | none | `baseline`: decomposition tracking (unless `distance_sampler` is given) and residual ratio tracking NEE; `restir_baseline`: the same with light sampling only (no phase-sampled escape MIS) and Russian roulette by albedo, Lin et al. 2021's baseline exactly (§6, §6.1; give the medium `supervoxel = 8`) |

use super::shared::context::{MediumVertex, NextEvent, PathContext};
use super::shared::free_flight::next_collision;
use super::shared::next_event::{escaped, light_sample, phase_sample_to_environment};
use super::shared::{estimator_rng, primary_ray, DistanceSampler, PixelSample, ScatterParams};
use super::volpath::{VolPath, VolPathParams};
use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, Integrator, IntegratorParams};
use crate::lights::sample::LightSampler;
use crate::params::{Param, ParamReader};
use crate::world::World;
use fogbank_estimators::Estimator;
use fogbank_math::{SampleKey, Vec3};

/// `direct` takes exactly the scattering parameters `volpath` has besides
/// its path length.
pub type DirectParams = ScatterParams;
pub use super::shared::SCATTER_PARAMS as PARAMS;

impl IntegratorParams for ScatterParams {
    const NAME: &'static str = "direct";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: true,
        far_clip: true,
    };

    /// The table `volpath` reads too (`ScatterParams`' own reader).
    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        ScatterParams::read_scatter(r)
    }

    fn write(&self, t: &mut toml::Table) {
        self.write_scatter(t)
    }

    fn estimator(&self) -> Estimator {
        self.estimator
    }
}

#[derive(Clone, Debug)]
pub struct Direct {
    pub distance: DistanceSampler,
    pub nee: Estimator,
    pub lights: LightSampler,
    /// In a scene with surfaces or chromatic media, `volpath` with
    /// `max_depth = 1` renders (surfaces are then lit and occlude like
    /// media vertices; chromatic collisions may pass).
    with_surfaces: Option<Box<VolPath>>,
}

impl Direct {
    pub fn new(p: &DirectParams, world: &World) -> Result<Direct, SceneError> {
        let (distance, nee) = p.resolved();
        let chromatic = world.media.iter().any(|m| m.chroma.is_some());
        let with_surfaces = match world.surfaces.is_some() || chromatic {
            false => None,
            true => Some(Box::new(VolPath::new(
                &VolPathParams {
                    scatter: p.clone(),
                    max_depth: 1,
                    ..VolPathParams::default()
                },
                world,
            )?)),
        };
        Ok(Direct {
            distance,
            nee,
            lights: LightSampler::new(&world.lights, world.radius(), world.light_selection),
            with_surfaces,
        })
    }
}

impl Integrator for Direct {
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        if let Some(v) = &self.with_surfaces {
            return v.sample(world, x, y, key);
        }
        let mut rng = estimator_rng(key);
        let cx = &mut PathContext::new(world, &mut rng);
        let ray = primary_ray(world, x, y, key);
        let t_far = world.camera.ray_end(&ray);
        let Some((t, mi)) = next_collision(cx, self.distance.into(), &ray, t_far, None) else {
            let lost = world.lost_at_far_clip(None, &ray, t_far);
            return PixelSample {
                radiance: if lost {
                    Vec3::ZERO
                } else {
                    escaped(world, &self.lights, ray.d, None)
                },
                lookups: cx.lookups,
            };
        };
        let m = &world.media[mi];
        let p = ray.at(t);
        let albedo = m.albedo_at(p);
        let mut radiance = m.emitted(p, albedo);
        if albedo != Vec3::ZERO {
            let v = MediumVertex {
                p,
                d: ray.d,
                phase: m.phase,
                medium: None,
            };
            let nee = NextEvent {
                lights: &self.lights,
                shadow: self.nee.into(),
                mis: true,
            };
            radiance += albedo * light_sample(cx, &nee, &v);
            let (wi, pdf) = v.phase.sample(-ray.d, cx.next_2d());
            radiance += albedo * phase_sample_to_environment(cx, &nee, &v, wi, pdf);
        }
        let lookups = cx.lookups;
        PixelSample { radiance, lookups }
    }

    fn estimator(&self) -> Option<Estimator> {
        Some(self.nee)
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        Some(&mut self.nee)
    }
}

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

//!
//! | key | default | meaning |
//! |---|---|---|
//! | `distance_sampler` | `delta_tracking` | free-flight sampler: `delta_tracking`, `decomposition_tracking`, `regular_tracking` |
//! | `estimator` | `ratio_tracking` | NEE transmittance estimator (`fogbank estimators`), with its options |
//! | `preset` | none | `baseline`: decomposition tracking (unless `distance_sampler` is given) and residual ratio tracking NEE; `restir_baseline`: the same with light sampling only (no phase-sampled escape MIS) and roulette by albedo, seed 002's baseline exactly (§6; give the medium `supervoxel = 8`) |
//! | `max_depth` | 64 | longest path, in scattering vertices (1..=100000) |
//! | `rr_depth` | 3 | first bounce with Russian roulette on the throughput |
//! | `pins`, `tracking`, `march_step`, `pin_grid` | off | seed 004's pins and ray-marching baseline, see [`super::shared::pin_params`] |

use super::shared::free_flight::next_collision;
use super::shared::next_event::{escaped, light_sample_weighted, phase_sample_to_environment};
use super::shared::pin_params::{PinParams, PIN_KEYS};
use super::shared::tracking::PinSet;
use super::shared::{
    estimator_rng, primary_ray, PixelSample, Preset, ScatterParams, SCATTER_PARAMS,
};
use crate::error::SceneError;
use crate::lights::sample::LightSampler;
use crate::params::{Param, ParamReader};
use crate::world::phase::HenyeyGreenstein;
use crate::world::World;
use fogbank_estimators::Estimator;
use fogbank_math::{Ray, SampleKey, Vec3};
use std::sync::{Arc, OnceLock};

pub use super::shared::DistanceSampler;

pub const PARAMS: [Param; 9] = [
    SCATTER_PARAMS[0],
    SCATTER_PARAMS[1],
    SCATTER_PARAMS[2],
    Param {
        key: "max_depth",
        default: "64",
        meaning: "longest path, in scattering vertices (1..=100000)",
    },
    Param {
        key: "rr_depth",
        default: "3",
        meaning: "first bounce with Russian roulette on the throughput",
    },
    Param {
        key: PIN_KEYS[0],
        default: "off",
        meaning: "seed 004 pins: off, all, secondary (all but the view ray), ms (PinMS: multiple scattering only)",
    },
    Param {
        key: PIN_KEYS[1],
        default: "ray_marching with pins, else unbiased",
        meaning: "rays without pins: ray_marching (seed 004's baseline) or unbiased (distance_sampler + estimator)",
    },
    Param {
        key: PIN_KEYS[2],
        default: "0.03",
        meaning: "ray-marching step in edges of the medium's box",
    },
    Param {
        key: PIN_KEYS[3],
        default: "{}",
        meaning: "pin grid: positions, memory_ratio (0.1), phi (16), theta (4), step (0.01), jitter (1), mask_iterations (5), unquantised, seed",
    },
];

#[derive(Clone, Debug, PartialEq)]
pub struct VolPathParams {
    pub scatter: ScatterParams,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub pins: PinParams,
}

impl Default for VolPathParams {
    fn default() -> Self {
        VolPathParams {
            scatter: ScatterParams::default(),
            max_depth: 64,
            rr_depth: 3,
            pins: PinParams::default(),
        }
    }
}

impl VolPathParams {
    pub fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let scatter = ScatterParams::read(r)?;
        let max_depth = r.take("max_depth")?.unwrap_or(64);
        if max_depth == 0 || max_depth > 100_000 {
            return Err(SceneError(format!(
                "{}: {max_depth} is outside 1..=100000",
                r.key_path("max_depth")
            )));
        }
        Ok(VolPathParams {
            scatter,
            max_depth,
            rr_depth: r.take("rr_depth")?.unwrap_or(3),
            pins: PinParams::read(r)?,
        })
    }

    pub fn write(&self, t: &mut toml::Table) {
        self.scatter.write(t);
        t.insert("max_depth".into(), i64::from(self.max_depth).into());
        t.insert("rr_depth".into(), i64::from(self.rr_depth).into());
        self.pins.write(t);
    }
}

#[derive(Clone, Debug)]
pub struct VolPath {
    pub distance: DistanceSampler,
    pub nee: Estimator,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub lights: LightSampler,
    /// Seed 002's baseline: light sampling is the only strategy toward the
    /// lights, and roulette continues with the vertex albedo.
    pub light_only: bool,
    /// Which rays use pins, ray marching or the unbiased samplers.
    pub pins: PinParams,
    /// The media's pin grids when pins are on: gathered on the CPU when
    /// first needed (a GPU render gathers its own in a compute pass).
    pin_set: OnceLock<Option<Arc<PinSet>>>,
}

impl VolPath {
    pub fn new(p: &VolPathParams, world: &World) -> Result<VolPath, SceneError> {
        let (distance, nee) = p.scatter.resolved();
        Ok(VolPath {
            distance,
            nee,
            max_depth: p.max_depth,
            rr_depth: p.rr_depth,
            lights: LightSampler::new(&world.lights, world.radius()),
            light_only: p.scatter.preset == Some(Preset::RestirBaseline),
            pin_set: {
                // Checks every grid's size now; gathering waits.
                p.pins.plan(world)?;
                OnceLock::new()
            },
            pins: p.pins.clone(),
        })
    }

    /// The pin grids (gathered on first use; `None` with pins off).
    pub fn pin_set(&self, world: &World) -> Option<&PinSet> {
        self.pin_set
            .get_or_init(|| {
                // The plan was checked in `new`, so the gather cannot fail.
                self.pins.build(world).unwrap_or_default()
            })
            .as_deref()
    }

    pub fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let mut rng = estimator_rng(key);
        let mut ray = primary_ray(world, x, y, key);
        let (mut beta, mut radiance, mut lookups) = (Vec3::ONE, Vec3::ZERO, 0u32);
        let mut phase_pdf: Option<f32> = None;
        let set = self.pin_set(world);
        for depth in 0..self.max_depth {
            let flight = self.pins.flight(depth, self.distance, set);
            let Some((t, mi)) = next_collision(flight, world, &ray, &mut rng, &mut lookups) else {
                if !(self.light_only && phase_pdf.is_some()) {
                    radiance += beta * escaped(world, &self.lights, ray.d, phase_pdf);
                }
                break;
            };
            let m = &world.media[mi];
            let p = ray.at(t);
            let albedo = m.albedo_at(p);
            radiance += beta * m.emitted(p, albedo);
            beta *= albedo;
            if beta == Vec3::ZERO {
                break;
            }
            let hg = HenyeyGreenstein { g: m.phase_g };
            let shadow = self.pins.shadow(depth, self.nee, set);
            radiance += beta
                * light_sample_weighted(
                    world,
                    &self.lights,
                    shadow,
                    p,
                    ray.d,
                    &hg,
                    !self.light_only,
                    &mut rng,
                    &mut lookups,
                );
            let (wi, pdf) = hg.sample(-ray.d, [rng.next_f32(), rng.next_f32()]);
            if depth + 1 == self.max_depth {
                if self.light_only {
                    break;
                }
                radiance += beta
                    * phase_sample_to_environment(
                        world,
                        &self.lights,
                        shadow,
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
                let q = if self.light_only {
                    albedo.max_element()
                } else {
                    beta.max_element()
                }
                .min(1.0);
                if rng.next_f32() >= q {
                    break;
                }
                beta /= q;
            }
        }
        PixelSample { radiance, lookups }
    }
}

//! `volpath`: multiple scattering with next-event estimation at every vertex.
//!
//! Free-flight distance sampling picks the next real collision across all
//! media (the first collision of independent processes whose extinctions
//! add); the path throughput gains the scattering medium's albedo. At every
//! vertex one light is chosen (`LightSampler`: by power, environments at a
//! quarter of it on surfaces) and its contribution is weighted by
//! the NEE transmittance estimate; environment lights combine light and
//! phase sampling with the balance heuristic; at the last vertex
//! (`max_depth`) the phase-sampled partner is evaluated with the NEE
//! estimator instead of being traced, so no MIS weight is left without its
//! partner. A real collision adds the medium's emission (σ_a/σ_t) L_e.
//! Russian roulette on the throughput after `rr_depth` bounces (Lin et al. 2021
//! uses 3).
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `distance_sampler` | delta_tracking | free-flight sampler: `delta_tracking`, `decomposition_tracking`, `regular_tracking` |
//! | `estimator` | ratio_tracking (roulette 0.03) | NEE transmittance estimator (`fogbank estimators`), with its options |
//! | `preset` | none | `baseline`: decomposition tracking (unless `distance_sampler` is given) and residual ratio tracking NEE; `restir_baseline`: the same with light sampling only (no phase-sampled escape MIS) and Russian roulette by albedo, Lin et al. 2021's baseline exactly (§6, §6.1; give the medium `supervoxel = 8`) |
//! | `max_depth` | 64 | longest path, in scattering vertices (1..=100000); between pbrt-v4's 5, which loses most of a cloud's light, and Mitsuba 3's unbounded (100000 here), which a white medium may keep going for a GPU wave's lifetime: on the built-in scene 64 loses 3·10⁻⁶ of the light, at albedo 0.99 and 4× its density 1.8 % (`docs/results/defaults.md`) |
//! | `rr_depth` | 3 | first bounce with Russian roulette on the throughput's largest channel (pbrt-v4: from the second, Mitsuba 3: from the fifth) |
//! | `pins` | off | Hansen 2025's pins: `off`, `all`, `secondary` (all but the view ray), `ms` (PinMS: multiple scattering only) |
//! | `tracking` | ray_marching with pins, else unbiased | rays without pins: `ray_marching` (Hansen 2025's baseline) or `unbiased` (`distance_sampler` + `estimator`) |
//! | `march_step` | 0.03 | ray-marching step in edges of the medium's box |
//! | `pin_grid` | {} | the pin grid (`shared::pin_params`): `positions`, `memory_ratio` (0.1), `phi` (16), `theta` (4), `step` (0.01), `jitter` (1), `mask_iterations` (5), `unquantised`, `seed`, `stream` (0: static; pins streamed into each grid before every pass), `stream_spacing` (0.1) |

use super::shared::context::{MediumVertex, NextEvent, PathContext, SurfaceVertex};
use super::shared::free_flight::{next_collision, MAX_CROSSINGS};
use super::shared::next_event::{
    emitter_weight, escaped, light_sample, light_sample_surface, phase_sample_to_environment,
    sampled_direction_to_lights, SampledFrom,
};
use super::shared::pin_params::{PinMode, PinParams, PIN_KEYS};
use super::shared::pin_stream::PinStream;
use super::shared::tracking::PinSet;
use super::shared::{
    estimator_rng, primary_ray, PixelSample, Preset, ScatterParams, SCATTER_PARAMS,
};
use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, Integrator, IntegratorParams};
use crate::lights::sample::{LightSampler, Vertex};
use crate::params::{Param, ParamReader};
use crate::world::chroma::ChromaEvent;
use crate::world::surfaces::{ShadingFrame, SurfaceHit};
use crate::world::World;
use fogbank_estimators::Estimator;
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};
use std::sync::{Arc, OnceLock};

pub use super::shared::DistanceSampler;

pub const PARAMS: [Param; 9] = [
    SCATTER_PARAMS[0],
    SCATTER_PARAMS[1],
    SCATTER_PARAMS[2],
    Param {
        key: "max_depth",
        default: "64",
        meaning: "longest path, in scattering vertices (1..=100000); between pbrt-v4's 5, which loses most of a cloud's light, and Mitsuba 3's unbounded (100000 here), which a white medium may keep going for a GPU wave's lifetime: on the built-in scene 64 loses 3·10⁻⁶ of the light, at albedo 0.99 and 4× its density 1.8 % (`docs/results/defaults.md`)",
    },
    Param {
        key: "rr_depth",
        default: "3",
        meaning: "first bounce with Russian roulette on the throughput's largest channel (pbrt-v4: from the second, Mitsuba 3: from the fifth)",
    },
    Param {
        key: PIN_KEYS[0],
        default: "off",
        meaning: "Hansen 2025's pins: `off`, `all`, `secondary` (all but the view ray), `ms` (PinMS: multiple scattering only)",
    },
    Param {
        key: PIN_KEYS[1],
        default: "ray_marching with pins, else unbiased",
        meaning: "rays without pins: `ray_marching` (Hansen 2025's baseline) or `unbiased` (`distance_sampler` + `estimator`)",
    },
    Param {
        key: PIN_KEYS[2],
        default: "0.03",
        meaning: "ray-marching step in edges of the medium's box",
    },
    Param {
        key: PIN_KEYS[3],
        default: "{}",
        meaning: "the pin grid (`shared::pin_params`): `positions`, `memory_ratio` (0.1), `phi` (16), `theta` (4), `step` (0.01), `jitter` (1), `mask_iterations` (5), `unquantised`, `seed`, `stream` (0: static; pins streamed into each grid before every pass), `stream_spacing` (0.1)",
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

impl IntegratorParams for VolPathParams {
    const NAME: &'static str = "volpath";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: true,
        far_clip: true,
    };

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let d = VolPathParams::default();
        let scatter = ScatterParams::read_scatter(r)?;
        let max_depth = r.take("max_depth")?.unwrap_or(d.max_depth);
        if max_depth == 0 || max_depth > 100_000 {
            return Err(SceneError(format!(
                "{}: {max_depth} is outside 1..=100000",
                r.key_path("max_depth")
            )));
        }
        Ok(VolPathParams {
            scatter,
            max_depth,
            rr_depth: r.take("rr_depth")?.unwrap_or(d.rr_depth),
            pins: PinParams::read(r)?,
        })
    }

    fn write(&self, t: &mut toml::Table) {
        self.scatter.write_scatter(t);
        t.insert("max_depth".into(), i64::from(self.max_depth).into());
        t.insert("rr_depth".into(), i64::from(self.rr_depth).into());
        self.pins.write(t);
    }

    fn estimator(&self) -> Estimator {
        self.scatter.estimator
    }
}

/// A path's state between vertices.
struct Path {
    ray: Ray,
    beta: Vec3,
    radiance: Vec3,
    /// The last scattering vertex, the solid-angle pdf its direction was
    /// sampled with and its kind, for MIS with light sampling (`None`:
    /// camera ray or delta lobe). Null boundaries leave it unchanged.
    prev: Option<SampledFrom>,
    /// The bounded medium the path is in (see `World::medium_active`).
    medium: Option<usize>,
}

/// What a vertex did to the path.
enum Step {
    Stop,
    /// A scattering vertex: the path is one longer.
    Scatter,
    /// Straight through an index-matched boundary: not a vertex.
    Cross,
    /// A null collision of a chromatic medium: not a vertex either.
    Null,
}

/// Null collisions of chromatic media one path may take (a guard against
/// endless loops, far above what any medium needs).
const MAX_NULL_COLLISIONS: u32 = 1 << 24;

#[derive(Clone, Debug)]
pub struct VolPath {
    pub distance: DistanceSampler,
    pub nee: Estimator,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub lights: LightSampler,
    /// Lin et al. 2021's baseline: light sampling is the only strategy toward the
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
            lights: LightSampler::new(&world.lights, world.radius(), world.light_selection),
            light_only: p.scatter.preset == Some(Preset::RestirBaseline),
            pin_set: {
                if p.pins.mode != PinMode::Off && world.media.iter().any(|m| m.chroma.is_some()) {
                    return Err(SceneError(
                        "integrator.pins: pins store one extinction per cell; chromatic media (sigma_t_scale = [r, g, b]) cannot use them".into(),
                    ));
                }
                // Checks every grid's size now; gathering waits.
                p.pins.plan(world)?;
                OnceLock::new()
            },
            pins: p.pins.clone(),
        })
    }

    /// Replaces the pin grids (the pin stream between frames,
    /// `shared::pin_stream`); `None` turns pins' grids off.
    pub fn set_pin_set(&mut self, set: Option<Arc<PinSet>>) {
        self.pin_set = OnceLock::from(set);
    }

    /// The pin grids (gathered on first use; `None` with pins off).
    pub fn pin_set(&self, world: &World) -> Option<&PinSet> {
        self.gathered(world).map(|s| &**s)
    }

    fn gathered(&self, world: &World) -> Option<&Arc<PinSet>> {
        self.pin_set
            .get_or_init(|| {
                // The plan was checked in `new`, so the gather cannot fail.
                self.pins.build(world).unwrap_or_default()
            })
            .as_ref()
    }

    /// The render-time pin stream (`pin_grid.stream`), when on: the
    /// render loop asks it for each pass's grids and renders the pass with
    /// [`VolPath::sample_with`].
    pub fn pin_stream(&self, world: &World) -> Option<PinStream> {
        self.pins.stream(self.gathered(world))
    }

    /// [`VolPath::sample`] with the pin grids `set` (a pass of the stream).
    pub fn sample_with(
        &self,
        world: &World,
        x: u32,
        y: u32,
        key: SampleKey,
        set: Option<&PinSet>,
    ) -> PixelSample {
        let mut rng = estimator_rng(key);
        let cx = &mut PathContext::new(world, &mut rng);
        let mut path = Path {
            ray: primary_ray(world, x, y, key),
            beta: Vec3::ONE,
            radiance: Vec3::ZERO,
            prev: None,
            medium: world.surfaces.as_ref().and_then(|s| s.camera_medium),
        };
        let (mut depth, mut crossings, mut nulls) = (0, 0u32, 0u32);
        // The camera ray's first segment ends on the far clip plane.
        let camera_end = world.camera.ray_end(&path.ray);
        while depth < self.max_depth {
            let from_camera = depth == 0 && crossings == 0 && nulls == 0;
            let t_limit = if from_camera {
                camera_end
            } else {
                f32::INFINITY
            };
            let hit = world
                .surfaces
                .as_ref()
                .and_then(|s| s.intersect(&path.ray, t_limit));
            let t_end = hit.map_or(t_limit, |h| h.t);
            let flight = self.pins.flight(depth, self.distance, set);
            let (ray, medium) = (path.ray, path.medium);
            let collision = next_collision(cx, flight, &ray, t_end, medium);
            let step = match (collision, hit) {
                (Some((t, mi)), _) => self.medium_vertex(cx, &mut path, t, mi, depth),
                (None, Some(h)) => self.surface_vertex(cx, &mut path, &h, depth),
                (None, None) if from_camera && world.lost_at_far_clip(medium, &ray, t_limit) => {
                    Step::Stop
                }
                (None, None) => {
                    if !(self.light_only && path.prev.is_some()) {
                        let le = escaped(world, &self.lights, path.ray.d, path.prev);
                        path.radiance += path.beta * le;
                    }
                    Step::Stop
                }
            };
            match step {
                Step::Stop => break,
                Step::Scatter => depth += 1,
                Step::Cross => {
                    crossings += 1;
                    if crossings > MAX_CROSSINGS {
                        break;
                    }
                }
                Step::Null => {
                    nulls += 1;
                    if nulls > MAX_NULL_COLLISIONS {
                        break;
                    }
                }
            }
        }
        PixelSample {
            radiance: path.radiance,
            lookups: cx.lookups,
        }
    }

    /// A real collision in medium `mi` at distance `t`: emission, NEE with
    /// the phase function, then phase sampling (or, at the last vertex, the
    /// phase-sampled direction evaluated toward the lights).
    fn medium_vertex(
        &self,
        cx: &mut PathContext,
        path: &mut Path,
        t: f32,
        mi: usize,
        depth: u32,
    ) -> Step {
        let m = &cx.world.media[mi];
        let p = path.ray.at(t);
        let d = path.ray.d;
        let mut albedo = m.albedo_at(p);
        if let Some(c) = &m.chroma {
            // A collision of the tracked (largest) channel: each channel
            // scatters, absorbs (emits) or passes with its own probability.
            let k = c.k_at(&m.medium, p, &mut cx.lookups);
            path.radiance += path.beta * (m.emitted(p, albedo) * k);
            match c.event(path.beta, albedo, k, cx.next_f32()) {
                ChromaEvent::Scatter(w) => albedo = w,
                ChromaEvent::Pass(w) => {
                    path.beta *= w;
                    path.ray = Ray::new(p, d);
                    return Step::Null;
                }
                ChromaEvent::Stop => return Step::Stop,
            }
        } else {
            path.radiance += path.beta * m.emitted(p, albedo);
        }
        path.beta *= albedo;
        if path.beta == Vec3::ZERO {
            return Step::Stop;
        }
        let v = MediumVertex {
            p,
            d,
            phase: m.phase,
            medium: path.medium,
        };
        let nee = self.next_event(cx.world, depth);
        path.radiance += path.beta * light_sample(cx, &nee, &v);
        let (wi, pdf) = v.phase.sample(-d, cx.next_2d());
        if depth + 1 == self.max_depth {
            if !self.light_only {
                path.radiance += path.beta * phase_sample_to_environment(cx, &nee, &v, wi, pdf);
            }
            return Step::Stop;
        }
        path.prev = Some(SampledFrom {
            p,
            pdf,
            at: Vertex::Medium,
        });
        path.ray = Ray::new(p, wi);
        self.roulette(path, depth, albedo, cx.rng)
    }

    /// Next-event estimation at a vertex of depth `depth`: this
    /// integrator's light strategy, the shadow estimator for that depth
    /// (PinMS switches to pins past the first bounce), MIS unless light
    /// sampling is the only strategy.
    fn next_event(&self, world: &World, depth: u32) -> NextEvent<'_> {
        NextEvent {
            lights: &self.lights,
            shadow: self.pins.shadow(depth, self.nee, self.pin_set(world)),
            mis: !self.light_only,
        }
    }

    /// A surface hit: its emission (MIS-weighted against light sampling),
    /// then straight through a null boundary, or NEE with the BSDF and BSDF
    /// sampling (at the last vertex, the sampled direction evaluated
    /// toward the lights).
    fn surface_vertex(
        &self,
        cx: &mut PathContext,
        path: &mut Path,
        h: &SurfaceHit,
        depth: u32,
    ) -> Step {
        let world = cx.world;
        let surfaces = world.surfaces.as_ref().expect("a hit has surfaces");
        let d = path.ray.d;
        if let Some((le, li)) = surfaces.emitted(h, d) {
            if !(self.light_only && path.prev.is_some()) {
                let w = emitter_weight(world, &self.lights, li, h.p, d, path.prev);
                path.radiance += path.beta * le * w;
            }
        }
        let material = &surfaces.shapes[h.shape as usize].material;
        if material.is_null() {
            path.medium = surfaces.target_medium(h, d, path.medium);
            path.ray = h.spawn(d);
            return Step::Cross;
        }
        let bsdf = material.at(h.uv);
        let frame = ShadingFrame::new(h.ns);
        let wo = frame.to_local(-d);
        let nee = self.next_event(world, depth);
        if !bsdf.is_delta() {
            let v = SurfaceVertex {
                hit: h,
                frame,
                wo,
                bsdf: &bsdf,
                medium: path.medium,
            };
            path.radiance += path.beta * light_sample_surface(cx, &nee, &v);
        }
        let uc = cx.next_f32();
        let Some(bs) = bsdf.sample(wo, uc, cx.next_2d()) else {
            return Step::Stop;
        };
        let weight = bs.weight();
        if !(weight.is_finite() && weight.max_element() > 0.0) {
            return Step::Stop;
        }
        let wi = frame.to_world(bs.wi);
        let prev = (!bs.delta).then_some(SampledFrom {
            p: h.p,
            pdf: bs.pdf,
            at: Vertex::Surface,
        });
        let medium = surfaces.target_medium(h, wi, path.medium);
        if bs.delta && bs.wi == -wo && material.passes_light() {
            // Straight through a thin dielectric: a null event as in
            // Mitsuba (no vertex; MIS keeps the last real vertex), the
            // partner of shadow rays' 1 − R′.
            path.beta *= weight;
            path.medium = medium;
            path.ray = h.spawn(d);
            return Step::Cross;
        }
        if depth + 1 == self.max_depth {
            if !self.light_only {
                let ray = h.spawn(wi);
                path.radiance +=
                    path.beta * weight * sampled_direction_to_lights(cx, &nee, &ray, prev, medium);
            }
            return Step::Stop;
        }
        path.beta *= weight;
        path.prev = prev;
        path.medium = medium;
        path.ray = h.spawn(wi);
        self.roulette(path, depth, weight, cx.rng)
    }

    /// Russian roulette on the throughput from `rr_depth` on (Lin et al. 2021's
    /// baseline: on the vertex albedo, `albedo`).
    fn roulette(&self, path: &mut Path, depth: u32, albedo: Vec3, rng: &mut Pcg32) -> Step {
        if depth + 1 >= self.rr_depth {
            let q = if self.light_only {
                albedo.max_element()
            } else {
                path.beta.max_element()
            }
            .min(1.0);
            if rng.next_f32() >= q {
                return Step::Stop;
            }
            path.beta /= q;
        }
        Step::Scatter
    }
}

impl Integrator for VolPath {
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        self.sample_with(world, x, y, key, self.pin_set(world))
    }

    fn estimator(&self) -> Option<Estimator> {
        Some(self.nee)
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        Some(&mut self.nee)
    }

    fn prepare(&self, world: &World) {
        self.pin_set(world);
    }
}

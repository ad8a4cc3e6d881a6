//! `ament`: the ray-marched extinction optimisation of Ament, Zirr and
//! Dachsbacher 2017 (AZD17), Lerzer and Dachsbacher 2025's baseline (§4, §6.2). Each camera
//! ray is marched twice with a fixed step: first to sum the importance of
//! its samples, then to composite with μ'_i = p μ_i / (p + (1 − g_i)^{2λ}
//! h_i), h_i = r Σ_{j<i} + q Σ_{j>i} of g_j², single scattering with a
//! deterministic, likewise optimised shadow ray to every light (cost grows
//! with the number of lights).
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `step` | 0.002 | Δx in the medium's [−1, 1]³ units (the paper's HEPTANE step) |
//! | `form` | normalised | `printed`: Eq. 3–4, sums without Δx (μ' → 0 as Δx → 0, Eq. 5, Fig. 2); `normalised`: Σ g_j² Δx, the paper's comparison form (Figs. 5–6) |
//! | `jitter` | false | one random start offset in [0, Δx) per pixel sample (Fig. 6's jittered variant) |
//! | `p` | 1 | weight of the data term, as `visopt` |
//! | `q` | 70 | weight of importance behind a sample, as `visopt` |
//! | `r` | 30 | weight of importance before a sample, as `visopt` |
//! | `lambda` | 1 | exponent of (1 − g)^{2λ}, as `visopt` |
//! | `optimise` | true | false: plain ray-marched DVR |
//! | `shading` | false | HG plus the gradient lobe, as `visopt` |
//! | `n` | 40 | the lobe's exponent |
//!
//! Importance is the medium's `[[media.importance]]` (post-interpolative,
//! as the paper's comparison replaces AZD17's own). Shapes are opaque black
//! occluders (`shared/occluders.rs`): camera rays are marched up to the
//! first surface and shadow rays a surface cuts carry no light.

use super::shared::next_event::delta_lights;
use super::shared::{estimator_rng, occluders, primary_ray, PixelSample};
use super::visopt::segments::mu_factor;
use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, Integrator, IntegratorParams};
use crate::params::{Param, ParamReader};
use crate::world::medium::SceneMedium;
use crate::world::shading::dvr_phase;
use crate::world::World;
use fogbank_estimators::estimator::RatioTracking;
use fogbank_estimators::Estimator;
use fogbank_math::{Ray, SampleKey, Vec3};

pub const PARAMS: [Param; 10] = [
    Param {
        key: "step",
        default: "0.002",
        meaning: "Δx in the medium's [−1, 1]³ units (the paper's HEPTANE step)",
    },
    Param {
        key: "form",
        default: "normalised",
        meaning: "`printed`: Eq. 3–4, sums without Δx (μ' → 0 as Δx → 0, Eq. 5, Fig. 2); `normalised`: Σ g_j² Δx, the paper's comparison form (Figs. 5–6)",
    },
    Param {
        key: "jitter",
        default: "false",
        meaning: "one random start offset in [0, Δx) per pixel sample (Fig. 6's jittered variant)",
    },
    Param {
        key: "p",
        default: "1",
        meaning: "weight of the data term, as `visopt`",
    },
    Param {
        key: "q",
        default: "70",
        meaning: "weight of importance behind a sample, as `visopt`",
    },
    Param {
        key: "r",
        default: "30",
        meaning: "weight of importance before a sample, as `visopt`",
    },
    Param {
        key: "lambda",
        default: "1",
        meaning: "exponent of (1 − g)^{2λ}, as `visopt`",
    },
    Param {
        key: "optimise",
        default: "true",
        meaning: "false: plain ray-marched DVR",
    },
    Param {
        key: "shading",
        default: "false",
        meaning: "HG plus the gradient lobe, as `visopt`",
    },
    Param {
        key: "n",
        default: "40",
        meaning: "the lobe's exponent",
    },
];

#[derive(Clone, Debug, PartialEq)]
pub struct AmentParams {
    pub step: f32,
    pub printed: bool,
    pub jitter: bool,
    pub p: f32,
    pub q: f32,
    pub r: f32,
    pub lambda: f32,
    pub optimise: bool,
    pub shading: bool,
    pub n: f32,
}

impl Default for AmentParams {
    fn default() -> Self {
        AmentParams {
            step: 0.002,
            printed: false,
            jitter: false,
            p: 1.0,
            q: 70.0,
            r: 30.0,
            lambda: 1.0,
            optimise: true,
            shading: false,
            n: 40.0,
        }
    }
}

impl IntegratorParams for AmentParams {
    const NAME: &'static str = "ament";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: false,
        far_clip: false,
    };

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let d = AmentParams::default();
        let mut num = |key: &str, default: f32, positive: bool| -> Result<f32, SceneError> {
            let v = r.take::<f64>(key)?.map_or(default, |v| v as f32);
            let ok = v.is_finite() && if positive { v > 0.0 } else { v >= 0.0 };
            if ok {
                Ok(v)
            } else {
                let bound = if positive { "> 0" } else { "≥ 0" };
                Err(SceneError(format!(
                    "{}: {v} must be finite and {bound}",
                    r.key_path(key)
                )))
            }
        };
        let step = num("step", d.step, true)?;
        let (p, q, rr, lambda, n) = (
            num("p", d.p, true)?,
            num("q", d.q, false)?,
            num("r", d.r, false)?,
            num("lambda", d.lambda, false)?,
            num("n", d.n, false)?,
        );
        let printed = match r.take::<String>("form")?.as_deref() {
            None | Some("normalised") => false,
            Some("printed") => true,
            Some(o) => {
                return Err(SceneError(format!(
                    "{}: `{o}` is not printed or normalised",
                    r.key_path("form")
                )))
            }
        };
        Ok(AmentParams {
            step,
            printed,
            jitter: r.take("jitter")?.unwrap_or(d.jitter),
            p,
            q,
            r: rr,
            lambda,
            optimise: r.take("optimise")?.unwrap_or(d.optimise),
            shading: r.take("shading")?.unwrap_or(d.shading),
            n,
        })
    }

    fn write(&self, t: &mut toml::Table) {
        for (k, v) in [
            ("step", self.step),
            ("p", self.p),
            ("q", self.q),
            ("r", self.r),
            ("lambda", self.lambda),
            ("n", self.n),
        ] {
            t.insert(k.into(), f64::from(v).into());
        }
        t.insert(
            "form".into(),
            if self.printed {
                "printed"
            } else {
                "normalised"
            }
            .into(),
        );
        for (k, v) in [
            ("jitter", self.jitter),
            ("optimise", self.optimise),
            ("shading", self.shading),
        ] {
            t.insert(k.into(), v.into());
        }
    }

    // Shadow rays are marched like camera rays; no estimator is read, and
    // visopt's (ratio tracking) stands for it in listings and kernel set-up.
    fn estimator(&self) -> Estimator {
        Estimator::RatioTracking(RatioTracking { roulette: 0.0 })
    }
}

#[derive(Clone, Debug)]
pub struct Ament {
    pub params: AmentParams,
    /// 2 / the medium's longest world extent.
    pub unit: f32,
}

/// The samples of one marched ray segment: world points and their μ_t and
/// importance.
struct March {
    points: Vec<Vec3>,
    sigma: Vec<f32>,
    g: Vec<f32>,
    /// World step.
    dt: f32,
}

impl Ament {
    pub fn new(p: &AmentParams, world: &World) -> Result<Ament, SceneError> {
        if world.media.len() != 1 {
            return Err(SceneError(format!(
                "integrator \"ament\" renders scenes with exactly one medium (this one has {})",
                world.media.len()
            )));
        }
        occluders::check(world, "ament")?;
        let b = world.media[0].medium.world_bounds();
        let extent = (b.max - b.min).max_element();
        if !(extent > 0.0 && extent.is_finite()) {
            return Err(SceneError(
                "integrator \"ament\": the medium has no extent".into(),
            ));
        }
        if world.lights.iter().any(|l| !l.is_delta()) {
            return Err(SceneError(
                "integrator \"ament\" marches a shadow ray to every light: point, spot and directional lights only".into(),
            ));
        }
        let unit = 2.0 / extent;
        let steps = 2.0 * 3f32.sqrt() / p.step;
        if steps > 1.0e6 {
            return Err(SceneError(format!(
                "integrator.step: {} gives {steps:.0} steps across the volume (more than 10⁶)",
                p.step
            )));
        }
        Ok(Ament {
            params: p.clone(),
            unit,
        })
    }

    /// Marches `[s0, s1]` of `ray` from `start` (a fraction of a step).
    fn march(&self, m: &SceneMedium, ray: &Ray, s0: f32, s1: f32, start: f32) -> March {
        let dt = self.params.step / self.unit;
        let n = (((s1 - s0) / dt - start).ceil().max(0.0)) as usize;
        let mut out = March {
            points: Vec::with_capacity(n),
            sigma: Vec::with_capacity(n),
            g: Vec::with_capacity(n),
            dt,
        };
        for i in 0..n {
            let s = s0 + (i as f32 + start) * dt;
            let p = ray.at(s);
            let sigma = m.sigma_t_smooth(p);
            out.points.push(p);
            out.sigma.push(sigma);
            out.g
                .push(super::visopt::optimised::importance_at(m, p, sigma));
        }
        out
    }

    /// μ'_i of every sample (Eq. 4, or with Σ g² Δx when normalised);
    /// `reversed`: x lies at the segment's end (light rays: the light plays
    /// the camera).
    fn optimised(&self, mk: &March, reversed: bool) -> Vec<f32> {
        let p = &self.params;
        if !p.optimise {
            return mk.sigma.clone();
        }
        let w = if p.printed { 1.0 } else { p.step };
        let sq: Vec<f32> = mk.g.iter().map(|g| g * g * w).collect();
        let total: f32 = sq.iter().sum();
        let mut before = 0.0f32;
        let mut out = vec![0.0; sq.len()];
        let order: Box<dyn Iterator<Item = usize>> = if reversed {
            Box::new((0..sq.len()).rev())
        } else {
            Box::new(0..sq.len())
        };
        for i in order {
            let after = (total - before - sq[i]).max(0.0);
            let h = p.r * before + p.q * after;
            out[i] = mk.sigma[i] * mu_factor(p.p, mk.g[i], p.lambda, h);
            before += sq[i];
        }
        out
    }

    /// Optimised transmittance from `p` toward a light `distance` away (0
    /// behind a surface).
    fn shadow(&self, world: &World, m: &SceneMedium, p: Vec3, wi: Vec3, distance: f32) -> f32 {
        let ray = Ray::new(p, wi);
        if !occluders::visible(world, &ray, distance) {
            return 0.0;
        }
        let Some((_, s0, s1)) = m.medium.to_index(&ray, 0.0, distance) else {
            return 1.0;
        };
        let mk = self.march(m, &ray, s0, s1, 0.5);
        let mu = self.optimised(&mk, true);
        (-mu.iter().map(|&v| (v * mk.dt) as f64).sum::<f64>()).exp() as f32
    }

    /// μ'/μ at each sample of the centre ray of pixel (x, y): Fig. 2 as
    /// numbers (the printed form shrinks with the step, the normalised
    /// form does not).
    pub fn factors(&self, world: &World, x: u32, y: u32) -> Vec<(Vec3, f32)> {
        let m = &world.media[0];
        let ray = world.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
        let t_end = occluders::first_surface(world, &ray);
        let Some((_, t0, t1)) = m.medium.to_index(&ray, 0.0, t_end) else {
            return Vec::new();
        };
        let mk = self.march(m, &ray, t0, t1, 0.5);
        let mu = self.optimised(&mk, false);
        mk.points
            .iter()
            .zip(mu.iter().zip(&mk.sigma))
            .filter(|(_, (_, &s))| s > 0.0)
            .map(|(p, (&o, &s))| (*p, o / s))
            .collect()
    }
}

impl Integrator for Ament {
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let mut rng = estimator_rng(key);
        let ray = primary_ray(world, x, y, key);
        let m = &world.media[0];
        // Marched up to the first surface (occluders.rs).
        let t_end = occluders::first_surface(world, &ray);
        let Some((_, t0, t1)) = m.medium.to_index(&ray, 0.0, t_end) else {
            return PixelSample {
                radiance: Vec3::ZERO,
                lookups: 0,
            };
        };
        let start = if self.params.jitter {
            rng.next_f32()
        } else {
            0.5
        };
        let mk = self.march(m, &ray, t0, t1, start);
        let mu = self.optimised(&mk, false);
        let (mut transmittance, mut radiance) = (1.0f32, Vec3::ZERO);
        let mut lookups = mk.points.len() as u32;
        for (i, &p) in mk.points.iter().enumerate() {
            let alpha = 1.0 - (-mu[i] * mk.dt).exp();
            if alpha <= 0.0 {
                continue;
            }
            let albedo = m.albedo_at(p);
            let lobe = self.params.shading.then_some(self.params.n);
            let f = |wi| dvr_phase(m, p, ray.d, wi, lobe, self.unit);
            let lit = delta_lights(world, p, f, |wi, distance| {
                lookups += 1;
                self.shadow(world, m, p, wi, distance)
            });
            radiance += transmittance * alpha * (m.emitted(p, albedo) + albedo * lit);
            transmittance *= 1.0 - alpha;
            if transmittance < 1e-4 {
                break;
            }
        }
        PixelSample { radiance, lookups }
    }

    /// Its shadow rays are ratio tracking by construction.
    fn estimator(&self) -> Option<Estimator> {
        None
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        None
    }

    fn occluders_only(&self) -> bool {
        true
    }
}

//! The estimator registry: names, options, descriptions, and the per-ray
//! dispatch over a medium's storage type.

use crate::jackknife::StepMode;
use crate::optical_depth::{Importance, Jitter};
use crate::roulette::DEFAULT_ROULETTE;
use fogbank_math::{Pcg32, Ray};
use fogbank_volume::{Medium, MediumView};

pub use crate::estimate::Estimate;

/// A transmittance estimator with its options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Estimator {
    RegularTracking,
    AnalyticTrilinear,
    TrackLength,
    /// `roulette`: the weight below which the walk plays Russian roulette
    /// (0: never; default [`DEFAULT_ROULETTE`]; [`crate::roulette`]).
    RatioTracking {
        roulette: f32,
    },
    ResidualRatioTracking {
        roulette: f32,
    },
    RayMarching {
        samples: u32,
        clip: bool,
    },
    BiasedRayMarching {
        doubled: bool,
    },
    UnbiasedRayMarching {
        mult: u32,
    },
    Jackknife {
        samples: u32,
        mode: StepMode,
        jitter: Jitter,
    },
    JackknifeNaive {
        samples: u32,
        jitter: Jitter,
    },
    JackknifeMeanImportance {
        samples: u32,
        jitter: Jitter,
    },
}

/// The estimator a scene gets when it names none: ratio tracking with its
/// default roulette (as pbrt-v4's and Mitsuba 3's shadow rays, unbiased
/// and bounded in cost however dense the medium).
impl Default for Estimator {
    fn default() -> Self {
        Estimator::RatioTracking {
            roulette: DEFAULT_ROULETTE,
        }
    }
}

/// Options as they come from a scene file or the command line; each
/// estimator accepts only its own.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EstimatorOptions {
    pub samples: Option<u32>,
    pub mode: Option<String>,
    pub step: Option<f32>,
    pub jitter: Option<String>,
    pub mult: Option<u32>,
    pub doubled: Option<bool>,
    pub clip: Option<bool>,
    pub roulette: Option<f32>,
}

/// One estimator's entry in the registry: its name, whether it is biased,
/// the option keys it takes (the single list `with_options` checks), their
/// defaults for `fogbank estimators`, and what it computes.
struct Info {
    name: &'static str,
    biased: bool,
    keys: &'static [&'static str],
    options: &'static str,
    description: &'static str,
}

const INFO: [Info; 11] = [
    Info {
        name: "regular_tracking",
        biased: false,
        keys: &[],
        options: "",
        description: "exact optical depth of the nearest-filtered grid by voxel DDA",
    },
    Info {
        name: "analytic_trilinear",
        biased: false,
        keys: &[],
        options: "",
        description: "exact optical depth of the trilinear interpolant (cubic per voxel)",
    },
    Info {
        name: "track_length",
        biased: false,
        keys: &[],
        options: "",
        description: "delta tracking with super-voxel majorants, returns 0 or 1",
    },
    Info {
        name: "ratio_tracking",
        biased: false,
        keys: &["roulette"],
        options: "roulette=0.03 (Russian roulette below this weight; 0: off)",
        description: "ratio tracking with super-voxel majorants (Novák et al. 2014)",
    },
    Info {
        name: "residual_ratio_tracking",
        biased: false,
        keys: &["roulette"],
        options: "roulette=0.03 (Russian roulette below this weight; 0: off)",
        description:
            "ratio tracking of the residual over a per-super-voxel control (Novák et al. 2014)",
    },
    Info {
        name: "ray_marching",
        biased: true,
        keys: &["samples", "clip"],
        options: "samples=10, clip=false",
        description: "exp(−X), N equidistant samples sharing one jitter",
    },
    Info {
        name: "biased_ray_marching",
        biased: true,
        keys: &["doubled"],
        options: "doubled=false",
        description: "Kettunen et al. 2021: exp(−X), mean importance, N_CMF samples",
    },
    Info {
        name: "unbiased_ray_marching",
        biased: false,
        keys: &["mult"],
        options: "mult=1",
        description: "Kettunen et al. 2021: power series, Russian roulette, U-statistics",
    },
    Info {
        name: "jackknife",
        biased: true,
        keys: &["samples", "mode", "step", "jitter"],
        options: "samples=10, mode=fixed_count|fixed_step, step=1.0, jitter=stratified|uniform",
        description:
            "Peters 2025: cos(S)·exp(−X̄) from two interleaved estimates (Alg. 1, 2; Eq. 4, 5)",
    },
    Info {
        name: "jackknife_naive",
        biased: true,
        keys: &["samples", "jitter"],
        options: "samples=10, jitter=stratified|uniform",
        description: "exp(−X) from one estimate of 2N samples, same machinery (Fig. 8c)",
    },
    Info {
        name: "jackknife_mean_importance",
        biased: true,
        keys: &["samples", "jitter"],
        options: "samples=10, jitter=stratified|uniform",
        description: "jackknife with mean importance and no control variate (Fig. 9 ablation)",
    },
];

/// A roulette threshold: a weight in [0, 1) (0: off).
fn parse_roulette(r: Option<f32>) -> Result<f32, String> {
    let r = r.unwrap_or(DEFAULT_ROULETTE);
    if !(0.0..1.0).contains(&r) {
        return Err(format!("roulette: {r} is outside [0, 1)"));
    }
    Ok(r)
}

/// Jackknife's step mode: a fixed sample count, or a fixed step in optical
/// depth (`step`, default 1).
fn parse_mode(o: &EstimatorOptions) -> Result<StepMode, String> {
    match o.mode.as_deref() {
        None | Some("fixed_count") => {
            if o.step.is_some() {
                return Err("step: only used with mode = \"fixed_step\"".into());
            }
            Ok(StepMode::FixedCount)
        }
        Some("fixed_step") => {
            let s = o.step.unwrap_or(1.0);
            if !(s > 0.0 && s.is_finite()) {
                return Err(format!("step: {s} must be a positive optical depth"));
            }
            Ok(StepMode::FixedStep(s))
        }
        Some(m) => Err(format!("mode: `{m}` is not fixed_count or fixed_step")),
    }
}

fn parse_jitter(j: &Option<String>) -> Result<Jitter, String> {
    match j.as_deref() {
        None | Some("stratified") => Ok(Jitter::Stratified),
        Some("uniform") => Ok(Jitter::Uniform),
        Some(o) => Err(format!("jitter: `{o}` is not stratified or uniform")),
    }
}

impl Estimator {
    pub fn names() -> Vec<&'static str> {
        INFO.iter().map(|i| i.name).collect()
    }

    /// Every estimator with default options.
    pub fn all() -> Vec<Estimator> {
        INFO.iter()
            .map(|i| Estimator::parse(i.name).expect("registered names parse"))
            .collect()
    }

    fn info(&self) -> &'static Info {
        let n = self.name();
        INFO.iter()
            .find(|i| i.name == n)
            .expect("every variant is registered")
    }

    pub fn name(&self) -> &'static str {
        match self {
            Estimator::RegularTracking => "regular_tracking",
            Estimator::AnalyticTrilinear => "analytic_trilinear",
            Estimator::TrackLength => "track_length",
            Estimator::RatioTracking { .. } => "ratio_tracking",
            Estimator::ResidualRatioTracking { .. } => "residual_ratio_tracking",
            Estimator::RayMarching { .. } => "ray_marching",
            Estimator::BiasedRayMarching { .. } => "biased_ray_marching",
            Estimator::UnbiasedRayMarching { .. } => "unbiased_ray_marching",
            Estimator::Jackknife { .. } => "jackknife",
            Estimator::JackknifeNaive { .. } => "jackknife_naive",
            Estimator::JackknifeMeanImportance { .. } => "jackknife_mean_importance",
        }
    }

    pub fn description(&self) -> &'static str {
        self.info().description
    }

    pub fn biased(&self) -> bool {
        self.info().biased
    }

    /// Options and defaults, for `fogbank estimators`.
    pub fn options_help(&self) -> &'static str {
        self.info().options
    }

    /// The option keys estimator `name` takes (`None`: no such estimator).
    pub fn option_keys(name: &str) -> Option<&'static [&'static str]> {
        INFO.iter().find(|i| i.name == name).map(|i| i.keys)
    }

    /// The options that give this estimator back through
    /// [`Estimator::with_options`] (every option it takes, spelled out).
    pub fn options(&self) -> EstimatorOptions {
        let jitter = |j: Jitter| {
            Some(match j {
                Jitter::Stratified => "stratified".to_string(),
                Jitter::Uniform => "uniform".to_string(),
            })
        };
        let mut o = EstimatorOptions::default();
        match *self {
            Estimator::RayMarching { samples, clip } => {
                o.samples = Some(samples);
                o.clip = Some(clip);
            }
            Estimator::BiasedRayMarching { doubled } => o.doubled = Some(doubled),
            Estimator::RatioTracking { roulette }
            | Estimator::ResidualRatioTracking { roulette } => o.roulette = Some(roulette),
            Estimator::UnbiasedRayMarching { mult } => o.mult = Some(mult),
            Estimator::Jackknife {
                samples,
                mode,
                jitter: j,
            } => {
                o.samples = Some(samples);
                match mode {
                    StepMode::FixedCount => o.mode = Some("fixed_count".into()),
                    StepMode::FixedStep(s) => {
                        o.mode = Some("fixed_step".into());
                        o.step = Some(s);
                    }
                }
                o.jitter = jitter(j);
            }
            Estimator::JackknifeNaive { samples, jitter: j }
            | Estimator::JackknifeMeanImportance { samples, jitter: j } => {
                o.samples = Some(samples);
                o.jitter = jitter(j);
            }
            _ => {}
        }
        o
    }

    /// An estimator from the command line: `NAME` or `NAME:KEY=VALUE:…`
    /// (`ratio_tracking:roulette=0.1`, `jackknife:samples=20:jitter=uniform`).
    pub fn parse_spec(spec: &str) -> Result<Estimator, String> {
        let (name, options) = spec.split_once(':').unwrap_or((spec, ""));
        let mut o = EstimatorOptions::default();
        for kv in options.split(':').filter(|s| !s.trim().is_empty()) {
            let (k, v) = kv
                .split_once('=')
                .ok_or_else(|| format!("`{spec}`: expected KEY=VALUE, got `{kv}`"))?;
            let (k, v) = (k.trim(), v.trim());
            let num = |what| format!("`{spec}`: {k} = `{v}` is not {what}");
            match k {
                "samples" => o.samples = Some(v.parse().map_err(|_| num("a count"))?),
                "mult" => o.mult = Some(v.parse().map_err(|_| num("a count"))?),
                "step" => o.step = Some(v.parse().map_err(|_| num("a number"))?),
                "roulette" => o.roulette = Some(v.parse().map_err(|_| num("a number"))?),
                "doubled" => o.doubled = Some(v.parse().map_err(|_| num("true or false"))?),
                "clip" => o.clip = Some(v.parse().map_err(|_| num("true or false"))?),
                "mode" => o.mode = Some(v.to_string()),
                "jitter" => o.jitter = Some(v.to_string()),
                _ => return Err(format!("`{spec}`: estimator `{name}` has no option `{k}`")),
            }
        }
        Estimator::with_options(name, &o).map_err(|e| format!("`{spec}`: {e}"))
    }

    /// The same estimator with Russian roulette off: the plain ratio and
    /// residual ratio tracking that Peters 2025's studies compare; every other
    /// estimator unchanged.
    pub fn without_roulette(self) -> Estimator {
        match self {
            Estimator::RatioTracking { .. } => Estimator::RatioTracking { roulette: 0.0 },
            Estimator::ResidualRatioTracking { .. } => {
                Estimator::ResidualRatioTracking { roulette: 0.0 }
            }
            e => e,
        }
    }

    /// The estimator `name` with default options.
    pub fn parse(name: &str) -> Option<Estimator> {
        Estimator::with_options(name, &EstimatorOptions::default()).ok()
    }

    /// The estimator `name` with `o` applied; an option the estimator does
    /// not take, or a bad value, is an error naming it.
    pub fn with_options(name: &str, o: &EstimatorOptions) -> Result<Estimator, String> {
        let allowed = Estimator::option_keys(name).unwrap_or(&[]);
        let given = [
            ("samples", o.samples.is_some()),
            ("mode", o.mode.is_some()),
            ("step", o.step.is_some()),
            ("jitter", o.jitter.is_some()),
            ("mult", o.mult.is_some()),
            ("doubled", o.doubled.is_some()),
            ("clip", o.clip.is_some()),
            ("roulette", o.roulette.is_some()),
        ];
        if let Some((bad, _)) = given.iter().find(|(k, set)| *set && !allowed.contains(k)) {
            return Err(format!("estimator `{name}` has no option `{bad}`"));
        }
        let samples = o.samples.unwrap_or(10);
        if samples == 0 || samples > 1 << 20 {
            return Err(format!("samples: {samples} is outside 1..=1048576"));
        }
        Ok(match name {
            "regular_tracking" => Estimator::RegularTracking,
            "analytic_trilinear" => Estimator::AnalyticTrilinear,
            "track_length" => Estimator::TrackLength,
            "ratio_tracking" => Estimator::RatioTracking {
                roulette: parse_roulette(o.roulette)?,
            },
            "residual_ratio_tracking" => Estimator::ResidualRatioTracking {
                roulette: parse_roulette(o.roulette)?,
            },
            "ray_marching" => Estimator::RayMarching {
                samples,
                clip: o.clip.unwrap_or(false),
            },
            "biased_ray_marching" => Estimator::BiasedRayMarching {
                doubled: o.doubled.unwrap_or(false),
            },
            "unbiased_ray_marching" => {
                let mult = o.mult.unwrap_or(1);
                if !(1..=16).contains(&mult) {
                    return Err(format!("mult: {mult} is outside 1..=16"));
                }
                Estimator::UnbiasedRayMarching { mult }
            }
            "jackknife" => Estimator::Jackknife {
                samples,
                mode: parse_mode(o)?,
                jitter: parse_jitter(&o.jitter)?,
            },
            "jackknife_naive" => Estimator::JackknifeNaive {
                samples,
                jitter: parse_jitter(&o.jitter)?,
            },
            "jackknife_mean_importance" => Estimator::JackknifeMeanImportance {
                samples,
                jitter: parse_jitter(&o.jitter)?,
            },
            other => {
                return Err(format!(
                    "unknown estimator `{other}` (available: {})",
                    Estimator::names().join(", ")
                ))
            }
        })
    }
}

fn exact((tau, lookups): (f64, u32)) -> Estimate {
    Estimate {
        transmittance: (-tau).exp() as f32,
        lookups,
    }
}

/// Transmittance of `medium` along the world-space ray over `[0, t_max]`.
pub fn transmittance(
    e: Estimator,
    medium: &Medium,
    world: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
) -> Estimate {
    use crate::*;
    use fogbank_math::RaySegment;
    let Some((r, t0, t1)) = medium.to_index(world, 0.0, t_max) else {
        return Estimate::ONE;
    };
    let seg = RaySegment::new(r, t0, t1);
    let view = medium.view();
    match e {
        Estimator::RegularTracking => match view {
            MediumView::F16(v) => exact(regular_tracking::optical_depth(&v, &seg)),
            MediumView::F32(v) => exact(regular_tracking::optical_depth(&v, &seg)),
            MediumView::Analytic(a) => {
                exact((a.field.optical_depth(&r, t0, t1) * a.scale as f64, 0))
            }
        },
        Estimator::AnalyticTrilinear => match view {
            MediumView::F16(v) => exact(analytic_trilinear::optical_depth(&v, &seg)),
            MediumView::F32(v) => exact(analytic_trilinear::optical_depth(&v, &seg)),
            MediumView::Analytic(a) => {
                exact((a.field.optical_depth(&r, t0, t1) * a.scale as f64, 0))
            }
        },
        Estimator::TrackLength => {
            with_view!(view, v => track_length::transmittance(&v, &seg, rng))
        }
        Estimator::RatioTracking { roulette } => {
            with_view!(view, v => ratio_tracking::transmittance(&v, &seg, rng, roulette))
        }
        Estimator::ResidualRatioTracking { roulette } => {
            with_view!(view, v => Estimate::of_one_channel(
                residual_ratio_tracking::transmittance_scaled(&v, &seg, rng, [1.0], roulette)
            ))
        }
        Estimator::RayMarching { samples, clip } => {
            with_view!(view, v => ray_marching::transmittance(&v, &seg, samples, clip, rng))
        }
        Estimator::BiasedRayMarching { doubled } => {
            with_view!(view, v => kettunen::biased_transmittance(&v, &seg, doubled, rng))
        }
        Estimator::UnbiasedRayMarching { mult } => {
            with_view!(view, v => kettunen::unbiased_transmittance(&v, &seg, mult, rng))
        }
        Estimator::Jackknife {
            samples,
            mode,
            jitter,
        } => {
            let sampling = jackknife::Sampling {
                mode,
                ..jackknife::Sampling::fixed_count(samples, jitter)
            };
            with_view!(view, v => jackknife::transmittance(&v, &seg, sampling, rng))
        }
        Estimator::JackknifeNaive { samples, jitter } => {
            with_view!(view, v => jackknife::naive_transmittance(&v, &seg, samples, jitter, rng))
        }
        Estimator::JackknifeMeanImportance { samples, jitter } => {
            let sampling = jackknife::Sampling {
                importance: Importance::Mean,
                ..jackknife::Sampling::fixed_count(samples, jitter)
            };
            with_view!(view, v => jackknife::transmittance(&v, &seg, sampling, rng))
        }
    }
}

#[cfg(test)]
mod estimator_test {
    use super::*;

    #[test]
    fn specs_give_options_and_refuse_what_an_estimator_lacks() {
        assert_eq!(
            Estimator::parse_spec("ratio_tracking:roulette=0.1"),
            Ok(Estimator::RatioTracking { roulette: 0.1 })
        );
        assert_eq!(
            Estimator::parse_spec("residual_ratio_tracking:roulette=0"),
            Ok(Estimator::ResidualRatioTracking { roulette: 0.0 })
        );
        assert_eq!(
            Estimator::parse_spec("jackknife:samples=20:jitter=uniform"),
            Ok(Estimator::Jackknife {
                samples: 20,
                mode: StepMode::FixedCount,
                jitter: Jitter::Uniform
            })
        );
        for bad in [
            "ratio_tracking:samples=3",
            "ratio_tracking:roulette=1.5",
            "ratio_tracking:roulette=x",
            "track_length:roulette=0.1",
            "nope",
            "jackknife:samples",
        ] {
            assert!(Estimator::parse_spec(bad).is_err(), "{bad}");
        }
        // Options survive the round trip through EstimatorOptions.
        let e = Estimator::RatioTracking { roulette: 0.25 };
        assert_eq!(Estimator::with_options(e.name(), &e.options()), Ok(e));
    }

    /// Both trackers play roulette unless told not to, and `fogbank
    /// estimators` states the default the parser uses.
    #[test]
    fn trackers_play_roulette_by_default() {
        const { assert!(DEFAULT_ROULETTE > 0.0) };
        for name in ["ratio_tracking", "residual_ratio_tracking"] {
            let e = Estimator::parse(name).unwrap();
            assert_eq!(e.options().roulette, Some(DEFAULT_ROULETTE), "{name}");
            let said = format!("roulette={DEFAULT_ROULETTE} ");
            assert!(
                e.options_help().starts_with(&said),
                "{name}: {}",
                e.options_help()
            );
            assert_eq!(e.without_roulette().options().roulette, Some(0.0));
        }
        let j = Estimator::parse("jackknife").unwrap();
        assert_eq!(j.without_roulette(), j);
    }
}

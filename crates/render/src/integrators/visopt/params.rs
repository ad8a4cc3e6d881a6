//! The parameters of `visopt` and their validation. Defaults the paper
//! gives: p, q, r, λ = 1, 70, 30, 1 and 200 light-ray samples (§6); one
//! uniform and three adaptive passes (§5.2). Defaults it leaves open
//! (checklist §2): N = 64 samples per pass, merge distance 2·L/N, half of
//! the adaptive strata at change points, q/r on light rays as on camera
//! rays with the light playing the camera.

use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, IntegratorParams};
use crate::params::{Param, ParamReader};
use fogbank_estimators::estimator::RatioTracking;
use fogbank_estimators::Estimator;

pub const PARAMS: [Param; 14] = [
    Param {
        key: "p",
        default: "1",
        meaning: "Eq. 8: weight of the data term (> 0); lengths in the medium's [−1, 1]³ units",
    },
    Param { key: "q", default: "70", meaning: "Eq. 7: weight of important matter behind a point: thins occluders" },
    Param { key: "r", default: "30", meaning: "Eq. 7: weight of important matter in front of a point: thins background clutter" },
    Param { key: "lambda", default: "1", meaning: "Eq. 8: exponent of (1 − g)^{2λ}" },
    Param { key: "samples", default: "64", meaning: "N, importance samples per camera ray and pass" },
    Param {
        key: "passes",
        default: "4",
        meaning: "1 uniform + (passes − 1) adaptive camera-list passes, then the lists are frozen",
    },
    Param { key: "merge_distance", default: "0 (auto: 2·L/N)", meaning: "d of Alg. 1, in [−1, 1]³ units; 0 picks 2·L/N per ray" },
    Param { key: "gap_share", default: "0.5", meaning: "share of adaptive strata at change points and ray ends" },
    Param {
        key: "light_samples",
        default: "200",
        meaning: "importance samples of each NEE ray's list (0: light rays unoptimised)",
    },
    Param {
        key: "scattering",
        default: "single",
        meaning: "`single`, `first` (optimised first NEE + plain multiple scattering), `all` (every NEE optimised)",
    },
    Param {
        key: "max_depth",
        default: "64",
        meaning: "longest path in scattering vertices, with `first` or `all`",
    },
    Param {
        key: "shading",
        default: "false",
        meaning: "add the gradient lobe ‖∇μ_t‖ (H·N)^n (N·ω_L)₊ to HG at NEE (§3; the paper enables it in Figs. 6 and 9)",
    },
    Param { key: "n", default: "40", meaning: "Blinn–Phong exponent of the lobe" },
    Param {
        key: "optimise",
        default: "true",
        meaning: "false: plain DVR (μ' = μ) with the same sampler",
    },
];

/// The three multiple-scattering settings of §5.4 (Fig. 9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scattering {
    /// Single scattering: one vertex, its NEE optimised.
    Single,
    /// The first vertex's NEE optimised, plain multiple scattering after it.
    First,
    /// Multiple scattering with every NEE optimised.
    All,
}

impl Scattering {
    pub const ALL: [Scattering; 3] = [Scattering::Single, Scattering::First, Scattering::All];

    pub fn name(self) -> &'static str {
        match self {
            Scattering::Single => "single",
            Scattering::First => "first",
            Scattering::All => "all",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct VisOptParams {
    pub p: f32,
    pub q: f32,
    pub r: f32,
    pub lambda: f32,
    pub samples: u32,
    pub passes: u32,
    pub merge_distance: f32,
    pub gap_share: f32,
    pub light_samples: u32,
    pub scattering: Scattering,
    pub max_depth: u32,
    pub shading: bool,
    pub n: f32,
    pub optimise: bool,
}

impl Default for VisOptParams {
    fn default() -> Self {
        VisOptParams {
            p: 1.0,
            q: 70.0,
            r: 30.0,
            lambda: 1.0,
            samples: 64,
            passes: 4,
            merge_distance: 0.0,
            gap_share: 0.5,
            light_samples: 200,
            scattering: Scattering::Single,
            max_depth: 64,
            shading: false,
            n: 40.0,
            optimise: true,
        }
    }
}

impl IntegratorParams for VisOptParams {
    const NAME: &'static str = "visopt";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: false,
        far_clip: false,
    };

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let d = VisOptParams::default();
        let mut f =
            |key: &str, default: f32, ok: fn(f32) -> bool, what: &str| -> Result<f32, SceneError> {
                let v: f32 = r.take::<f64>(key)?.map_or(default, |v| v as f32);
                if ok(v) {
                    Ok(v)
                } else {
                    Err(SceneError(format!("{}: {v} {what}", r.key_path(key))))
                }
            };
        let finite_pos = |v: f32| v > 0.0 && v.is_finite();
        let finite_nonneg = |v: f32| v >= 0.0 && v.is_finite();
        let p = VisOptParams {
            p: f("p", d.p, finite_pos, "must be finite and > 0")?,
            q: f("q", d.q, finite_nonneg, "must be finite and ≥ 0")?,
            r: f("r", d.r, finite_nonneg, "must be finite and ≥ 0")?,
            lambda: f("lambda", d.lambda, finite_nonneg, "must be finite and ≥ 0")?,
            merge_distance: f(
                "merge_distance",
                d.merge_distance,
                finite_nonneg,
                "must be finite and ≥ 0",
            )?,
            gap_share: f(
                "gap_share",
                d.gap_share,
                |v| (0.0..=1.0).contains(&v),
                "is outside [0, 1]",
            )?,
            n: f("n", d.n, finite_nonneg, "must be finite and ≥ 0")?,
            ..d
        };
        let mut count = |key: &str, default: u32, lo: u32, hi: u32| -> Result<u32, SceneError> {
            let v: u32 = r.take(key)?.unwrap_or(default);
            if (lo..=hi).contains(&v) {
                Ok(v)
            } else {
                Err(SceneError(format!(
                    "{}: {v} is outside {lo}..={hi}",
                    r.key_path(key)
                )))
            }
        };
        let samples = count("samples", d.samples, 1, 4096)?;
        let passes = count("passes", d.passes, 1, 64)?;
        let light_samples = count("light_samples", d.light_samples, 0, 4096)?;
        let max_depth = count("max_depth", d.max_depth, 1, 100_000)?;
        let scattering = match r.take::<String>("scattering")?.as_deref() {
            None => d.scattering,
            Some("single") => Scattering::Single,
            Some("first") => Scattering::First,
            Some("all") => Scattering::All,
            Some(other) => {
                return Err(SceneError(format!(
                    "{}: `{other}` is not single, first or all",
                    r.key_path("scattering")
                )))
            }
        };
        Ok(VisOptParams {
            samples,
            passes,
            light_samples,
            max_depth,
            scattering,
            shading: r.take("shading")?.unwrap_or(d.shading),
            optimise: r.take("optimise")?.unwrap_or(d.optimise),
            ..p
        })
    }

    fn write(&self, t: &mut toml::Table) {
        for (k, v) in [
            ("p", self.p),
            ("q", self.q),
            ("r", self.r),
            ("lambda", self.lambda),
            ("merge_distance", self.merge_distance),
            ("gap_share", self.gap_share),
            ("n", self.n),
        ] {
            t.insert(k.into(), f64::from(v).into());
        }
        for (k, v) in [
            ("samples", self.samples),
            ("passes", self.passes),
            ("light_samples", self.light_samples),
            ("max_depth", self.max_depth),
        ] {
            t.insert(k.into(), i64::from(v).into());
        }
        t.insert("scattering".into(), self.scattering.name().into());
        t.insert("shading".into(), self.shading.into());
        t.insert("optimise".into(), self.optimise.into());
    }

    // NEE rays are ratio-tracked through μ' (§5.3).
    fn estimator(&self) -> Estimator {
        Estimator::RatioTracking(RatioTracking { roulette: 0.0 })
    }
}

//! The parameters of `point_mis` (table in the module documentation).

use super::strategy::Strategy;
use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, IntegratorParams};
use crate::params::{estimator_value, take_estimator, Param, ParamReader};
use fogbank_estimators::Estimator;

/// Default N, lookups per optical-depth estimate of the MIS weights (seed
/// 000 §6.2: "our optical-depth estimator with N = 10").
pub const DEFAULT_MIS_SAMPLES: u32 = 10;

pub const PARAMS: [Param; 3] = [
    Param {
        key: "strategy",
        default: "mis_jackknife",
        meaning: "`free_flight`, `equiangular`, `mis_miller` (ratio-tracking weights from delta tracking's null collisions, Miller et al. 2019), `mis_naive` (Eq. 10 with g(X), m = 1; biased), `mis_jackknife` (Eq. 9, jackknife weights, unbiased), `mis_jackknife_biased` (Eq. 10)",
    },
    Param {
        key: "estimator",
        default: "ratio_tracking (roulette 0.03)",
        meaning: "transmittance estimator of the light ray (`fogbank estimators`), with its options",
    },
    Param {
        key: "mis_samples",
        default: "10",
        meaning: "lookups N per optical-depth estimate of the MIS weights (1..=4096)",
    },
];

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMisParams {
    pub strategy: Strategy,
    /// Transmittance estimator of the ray from the scattering point to the light.
    pub estimator: Estimator,
    pub mis_samples: u32,
}

impl Default for PointMisParams {
    fn default() -> Self {
        PointMisParams {
            strategy: Strategy::MisJackknife,
            estimator: Estimator::default(),
            mis_samples: DEFAULT_MIS_SAMPLES,
        }
    }
}

impl IntegratorParams for PointMisParams {
    const NAME: &'static str = "point_mis";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: false,
        far_clip: true,
    };

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let name = r
            .take::<String>("strategy")?
            .unwrap_or_else(|| "mis_jackknife".into());
        let strategy = Strategy::parse(&name).ok_or_else(|| {
            SceneError(format!(
                "{}: unknown strategy `{name}` (available: {})",
                r.key_path("strategy"),
                Strategy::ALL.map(Strategy::name).join(", ")
            ))
        })?;
        let mis_samples = r.take("mis_samples")?.unwrap_or(DEFAULT_MIS_SAMPLES);
        if mis_samples == 0 || mis_samples > 4096 {
            return Err(SceneError(format!(
                "{}: {mis_samples} is outside 1..=4096",
                r.key_path("mis_samples")
            )));
        }
        Ok(PointMisParams {
            strategy,
            estimator: take_estimator(r)?,
            mis_samples,
        })
    }

    fn write(&self, t: &mut toml::Table) {
        t.insert("strategy".into(), self.strategy.name().into());
        t.insert("estimator".into(), estimator_value(self.estimator));
        t.insert("mis_samples".into(), i64::from(self.mis_samples).into());
    }

    fn estimator(&self) -> Estimator {
        self.estimator
    }
}

//! `test_background`: an integrator that exists only in the render crate's
//! own tests, to show what adding one takes — this file and one line in
//! the `integrators!` list. It renders the media's transmittance (track
//! length) in front of a grey background of `level`.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `level` | 0.5 | radiance of the background, in every channel |

use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, IntegratorParams};
use crate::params::{Param, ParamReader};
use fogbank_estimators::estimator::TrackLength;
use fogbank_estimators::Estimator;

pub const PARAMS: [Param; 1] = [Param {
    key: "level",
    default: "0.5",
    meaning: "radiance of the background, in every channel",
}];

#[derive(Clone, Debug, PartialEq)]
pub struct TestBackground {
    pub level: f32,
}

impl Default for TestBackground {
    fn default() -> Self {
        TestBackground { level: 0.5 }
    }
}

impl IntegratorParams for TestBackground {
    const NAME: &'static str = "test_background";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: false,
        far_clip: true,
    };
    const LISTED: bool = false;

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let level: f32 = r.take("level")?.unwrap_or(TestBackground::default().level);
        if !(level.is_finite() && level >= 0.0) {
            return Err(SceneError(format!(
                "{}: {level} must be finite and ≥ 0",
                r.key_path("level")
            )));
        }
        Ok(TestBackground { level })
    }

    fn write(&self, t: &mut toml::Table) {
        t.insert("level".into(), f64::from(self.level).into());
    }

    fn estimator(&self) -> Estimator {
        Estimator::TrackLength(TrackLength)
    }
}

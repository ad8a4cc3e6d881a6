//! `test_tint`: a test-only integrator on both backends, to show what
//! adding one takes — this folder and one line of `integrators!`, then its
//! GPU folder (`crates/gpu/src/integrators/test_tint/`) and one line of
//! `gpu_integrators!`. Per sample, the media's transmittance along the
//! camera ray (track length) times `tint`, ramped across the image by the
//! pixel's column, (x + ½) / width, so that a port that mixed up its pixels
//! would show it.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `tint` | [1, 0.5, 0.25] | radiance behind the media at the right edge of the image |

use crate::error::SceneError;
use crate::integrators::plugin::{Capabilities, Integrator, IntegratorParams};
use crate::integrators::shared::{estimator_rng, primary_ray, PixelSample};
use crate::integrators::transmittance::along_ray;
use crate::params::{Param, ParamReader};
use crate::world::World;
use fogbank_estimators::estimator::TrackLength;
use fogbank_estimators::Estimator;
use fogbank_math::{SampleKey, Vec3};

pub const PARAMS: [Param; 1] = [Param {
    key: "tint",
    default: "[1, 0.5, 0.25]",
    meaning: "radiance behind the media at the right edge of the image",
}];

#[derive(Clone, Debug, PartialEq)]
pub struct TestTintParams {
    pub tint: [f32; 3],
}

impl Default for TestTintParams {
    fn default() -> Self {
        TestTintParams {
            tint: [1.0, 0.5, 0.25],
        }
    }
}

impl IntegratorParams for TestTintParams {
    const NAME: &'static str = "test_tint";
    const PARAMS: &'static [Param] = &PARAMS;
    const CAPABILITIES: Capabilities = Capabilities {
        chromatic: false,
        far_clip: true,
    };
    const LISTED: bool = false;

    fn read(r: &mut ParamReader) -> Result<Self, SceneError> {
        let tint: [f32; 3] = r.take("tint")?.unwrap_or(TestTintParams::default().tint);
        if !tint.iter().all(|c| c.is_finite() && *c >= 0.0) {
            return Err(SceneError(format!(
                "{}: {tint:?} must be finite and ≥ 0",
                r.key_path("tint")
            )));
        }
        Ok(TestTintParams { tint })
    }

    fn write(&self, t: &mut toml::Table) {
        let tint = self.tint.map(|c| toml::Value::from(f64::from(c)));
        t.insert("tint".into(), toml::Value::Array(tint.to_vec()));
    }

    fn estimator(&self) -> Estimator {
        Estimator::TrackLength(TrackLength)
    }
}

/// The built integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TestTint {
    pub tint: Vec3,
    pub estimator: Estimator,
}

impl TestTint {
    pub fn new(p: &TestTintParams) -> TestTint {
        TestTint {
            tint: Vec3::from(p.tint),
            estimator: p.estimator(),
        }
    }
}

impl Integrator for TestTint {
    fn sample(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
        let ray = primary_ray(world, x, y, key);
        let t_max = world.camera.ray_end(&ray);
        let mut rng = estimator_rng(key);
        let e = along_ray(world, self.estimator, &ray, t_max, &mut rng);
        let ramp = (x as f32 + 0.5) / world.camera.width as f32;
        PixelSample {
            radiance: self.tint * (ramp * e.transmittance),
            lookups: e.lookups,
        }
    }

    fn estimator(&self) -> Option<Estimator> {
        Some(self.estimator)
    }

    fn estimator_mut(&mut self) -> Option<&mut Estimator> {
        Some(&mut self.estimator)
    }
}

#[cfg(test)]
mod tests {
    use crate::integrators::{IntegratorKind, LISTED, REGISTRY};
    use crate::scene::{parse_scene, Scene, DEFAULT_SCENE};
    use crate::{render, Progress, RenderOptions};
    use std::path::Path;

    #[test]
    fn it_is_read_not_listed_and_renders_its_ramp() {
        assert!(REGISTRY.iter().any(|(n, _)| *n == "test_tint"));
        assert!(LISTED.iter().all(|(n, _)| *n != "test_tint"));
        let o: Vec<String> = [
            "integrator.type=test_tint",
            "integrator.tint=[2, 1, 0]",
            "camera.width=8",
            "camera.height=6",
            "media.0.density.resolution=16",
        ]
        .map(String::from)
        .to_vec();
        let desc = parse_scene(DEFAULT_SCENE, "built-in", &o).unwrap();
        let text = toml::to_string(&desc).unwrap();
        assert_eq!(parse_scene(&text, "round trip", &[]).unwrap(), desc);
        let scene = Scene::build(desc, Path::new(".")).unwrap();
        assert!(matches!(scene.integrator, IntegratorKind::TestTint(_)));
        let film = render(&scene, &RenderOptions::new(1, 1), &Progress::default()).film;
        for (i, p) in film.mean().iter().enumerate() {
            let ramp = ((i % 8) as f32 + 0.5) / 8.0;
            assert!((0.0..=2.0 * ramp + 1e-6).contains(&p[0]), "{i}: {p:?}");
            assert!((p[1] - p[0] / 2.0).abs() < 1e-6 && p[2] == 0.0, "{i}: {p:?}");
        }
        let e = parse_scene(DEFAULT_SCENE, "built-in", &["integrator.type=test_tint".into(), "integrator.tint=[1, -1, 0]".into()]).unwrap_err();
        assert!(e.0.contains("integrator.tint"), "{}", e.0);
    }
}

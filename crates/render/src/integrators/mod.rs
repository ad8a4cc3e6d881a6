//! Integrators: one file (or folder) each, registered here and only here.
//! An integrator maps a pixel sample (a key for its random streams) to
//! radiance and the lookups it cost, reading the [`World`]; its typed
//! parameter struct and parameter table live in its own file.
//!
//! Adding an integrator: its folder, with its parameter struct
//! implementing [`plugin::IntegratorParams`] (name, table, reader, writer,
//! estimator, capabilities) and its built form implementing
//! [`plugin::Integrator`] (sample, estimator, preparation), and one line in
//! the `integrators!` list below, which names both and says how the
//! description builds. The list generates [`IntegratorDesc`],
//! [`IntegratorKind`] and every dispatch over them.

pub mod ament;
pub mod direct;
pub mod plugin;
pub mod point_mis;
pub mod restir;
pub mod shared;
pub mod transmittance;
pub mod visopt;
pub mod volpath;

use crate::error::SceneError;
use crate::params::{Param, ParamReader};
use crate::world::World;
use ament::{Ament, AmentParams};
use direct::{Direct, DirectParams};
use fogbank_estimators::estimator::{AnalyticTrilinear, RatioTracking};
use fogbank_estimators::Estimator;
use fogbank_math::{SampleKey, Vec3};
use plugin::{Capabilities, Integrator, IntegratorParams};
use point_mis::{PointMis, PointMisParams};
use restir::{Restir, RestirParams};
use shared::PixelSample;
use std::sync::LazyLock;
use transmittance::{Transmittance, TransmittanceParams};
use visopt::{VisOpt, VisOptParams};
use volpath::{VolPath, VolPathParams};

/// The integrators, one line each: the variant, the parameter type (its
/// [`IntegratorParams`]), the built type (its [`Integrator`]), optionally
/// the module it declares (`in name`), and how the description builds it
/// for a world. Generates `IntegratorDesc`,
/// `IntegratorKind`, [`REGISTRY`] and every dispatch over them.
macro_rules! integrators {
    (@module [$($attr:tt)*] $module:ident) => {
        $($attr)* pub mod $module;
    };
    (@module [$($attr:tt)*]) => {};
    ($($(#[$meta:meta])* $variant:ident($params:ty => $kind:ty) $(in $module:ident)? => |$p:ident, $world:ident| $build:expr,)*) => {
        // A line may declare its module (`in test_tint`), so that a
        // test-only integrator is its folder and its line.
        $(integrators!(@module [$(#[$meta])*] $($module)?);)*

        /// The `[integrator]` table: `type` selects the integrator, every
        /// other key is one of its parameters (see each integrator's table).
        #[derive(Clone, Debug, PartialEq)]
        pub enum IntegratorDesc {
            $($(#[$meta])* $variant($params),)*
        }

        /// Every integrator this build reads: `type` and parameter table, in
        /// registration order (test-only ones included where compiled).
        pub static REGISTRY: LazyLock<Vec<(&'static str, &'static [Param])>> =
            LazyLock::new(registry);

        /// The integrators users see (`fogbank integrators`, the guide, the
        /// messages that list alternatives): [`REGISTRY`] less the test-only.
        pub static LISTED: LazyLock<Vec<(&'static str, &'static [Param])>> =
            LazyLock::new(|| {
                let mut v = Vec::new();
                $($(#[$meta])* if <$params>::LISTED {
                    v.push((<$params>::NAME, <$params>::PARAMS));
                })*
                v
            });

        // Entries may carry `#[cfg]`s, which `vec![]`'s elements cannot.
        #[allow(clippy::vec_init_then_push)]
        fn registry() -> Vec<(&'static str, &'static [Param])> {
            let mut v = Vec::new();
            $($(#[$meta])* v.push((<$params>::NAME, <$params>::PARAMS));)*
            v
        }

        impl IntegratorDesc {
            pub fn name(&self) -> &'static str {
                match self {
                    $($(#[$meta])* IntegratorDesc::$variant(_) => <$params>::NAME,)*
                }
            }

            /// The integrators with a capability, in registration order.
            fn names_with(has: fn(Capabilities) -> bool) -> Vec<&'static str> {
                let mut v = Vec::new();
                $($(#[$meta])* if <$params>::LISTED && has(<$params>::CAPABILITIES) {
                    v.push(<$params>::NAME);
                })*
                v
            }

            fn capabilities(&self) -> Capabilities {
                match self {
                    $($(#[$meta])* IntegratorDesc::$variant(_) => <$params>::CAPABILITIES,)*
                }
            }

            /// The transmittance estimator as given (before any preset).
            pub fn estimator(&self) -> Estimator {
                match self {
                    $($(#[$meta])* IntegratorDesc::$variant(p) => p.estimator(),)*
                }
            }

            fn write_params(&self, t: &mut toml::Table) {
                match self {
                    $($(#[$meta])* IntegratorDesc::$variant(p) => p.write(t),)*
                }
            }

            /// The description of integrator `name`, read from `r`.
            fn read_named(name: &str, r: &mut ParamReader) -> Result<Option<IntegratorDesc>, SceneError> {
                $($(#[$meta])* if name == <$params>::NAME {
                    return Ok(Some(IntegratorDesc::$variant(<$params>::read(r)?)));
                })*
                Ok(None)
            }

            fn build_kind(&self, world: &World) -> Result<IntegratorKind, SceneError> {
                Ok(match self {
                    $($(#[$meta])* IntegratorDesc::$variant($p) => {
                        let $world = world;
                        IntegratorKind::$variant($build)
                    })*
                })
            }
        }

        /// A built integrator.
        #[derive(Clone, Debug)]
        pub enum IntegratorKind {
            $($(#[$meta])* $variant($kind),)*
        }

        impl IntegratorKind {
            pub fn name(&self) -> &'static str {
                match self {
                    $($(#[$meta])* IntegratorKind::$variant(_) => <$params>::NAME,)*
                }
            }

            fn integrator(&self) -> &dyn Integrator {
                match self {
                    $($(#[$meta])* IntegratorKind::$variant(i) => i,)*
                }
            }

            fn integrator_mut(&mut self) -> &mut dyn Integrator {
                match self {
                    $($(#[$meta])* IntegratorKind::$variant(i) => i,)*
                }
            }

            /// One sample of pixel `(x, y)` with sample index `key.sample`
            /// (static dispatch: this is the render loop's call).
            pub fn sample_pixel(&self, world: &World, x: u32, y: u32, key: SampleKey) -> PixelSample {
                match self {
                    $($(#[$meta])* IntegratorKind::$variant(i) => i.sample(world, x, y, key),)*
                }
            }
        }
    };
}

integrators! {
    Transmittance(TransmittanceParams => Transmittance) => |p, _world| Transmittance {
        estimator: p.estimator,
        background: Vec3::from(p.background),
    },
    Direct(DirectParams => Direct) => |p, world| Direct::new(p, world)?,
    VolPath(VolPathParams => VolPath) => |p, world| VolPath::new(p, world)?,
    PointMis(PointMisParams => PointMis) => |p, world| PointMis::new(p, world)?,
    Restir(RestirParams => Restir) => |p, world| Restir::new(p, world)?,
    VisOpt(VisOptParams => VisOpt) => |p, world| VisOpt::new(p, world)?,
    Ament(AmentParams => Ament) => |p, world| Ament::new(p, world)?,
    // Test-only: compiled for this crate's tests and, through the
    // `test-plugins` feature, for the GPU crate's tests of its ports.
    #[cfg(any(test, feature = "test-plugins"))]
    TestBackground(test_background::TestBackground => Transmittance) in test_background => |p, _world| Transmittance {
        estimator: Estimator::TrackLength(fogbank_estimators::estimator::TrackLength),
        background: Vec3::splat(p.level),
    },
    #[cfg(any(test, feature = "test-plugins"))]
    TestTint(test_tint::TestTintParams => test_tint::TestTint) in test_tint => |p, _world| test_tint::TestTint::new(p),
}

/// A scene without `[integrator]` shows its media's transmittance over
/// `background`, which needs no light: fogbank's format is first the
/// estimators' workbench. pbrt-v4 defaults to `volpath` and Mitsuba 3 to
/// `path`; their readers write their format's integrator, and the built-in
/// scene names `volpath` (`docs/results/defaults.md`).
impl Default for IntegratorDesc {
    fn default() -> Self {
        IntegratorDesc::Transmittance(TransmittanceParams::default())
    }
}

impl IntegratorDesc {
    /// The typed description of the table at scene key `path`.
    pub fn from_table(path: &str, mut table: toml::Table) -> Result<IntegratorDesc, SceneError> {
        let ty = match table.remove("type") {
            None => "transmittance".to_string(),
            Some(toml::Value::String(s)) => s,
            Some(v) => {
                return Err(SceneError(format!(
                    "{path}.type: expected a string, got {}",
                    v.type_str()
                )))
            }
        };
        let Some(&(name, params)) = REGISTRY.iter().find(|(n, _)| *n == ty) else {
            let names: Vec<&str> = LISTED.iter().map(|(n, _)| *n).collect();
            return Err(SceneError(format!(
                "{path}.type: unknown integrator `{ty}` (available: {})",
                names.join(", ")
            )));
        };
        let mut r = ParamReader::new(path, name, table);
        let desc =
            IntegratorDesc::read_named(name, &mut r)?.expect("every registered integrator is read");
        // The estimator's options may stand flat in the table.
        let mut takes: Vec<&str> = params.iter().map(|p| p.key).collect();
        let estimator = desc.estimator();
        takes.extend_from_slice(Estimator::option_keys(estimator.name()).unwrap_or(&[]));
        let leftover = r.first_key();
        r.with_owner(&desc.owner())
            .finish(&takes)
            .map_err(|SceneError(e)| {
                let owners: Vec<&str> = LISTED
                    .iter()
                    .filter(|(_, ps)| ps.iter().any(|p| Some(p.key) == leftover.as_deref()))
                    .map(|(n, _)| *n)
                    .collect();
                match (leftover, owners.is_empty()) {
                    (Some(k), false) => SceneError(format!(
                        "{e} (`{k}` is a parameter of {})",
                        owners.join(", ")
                    )),
                    _ => SceneError(e),
                }
            })?;
        Ok(desc)
    }

    /// Who owns the table's keys, for messages: the integrator, and its
    /// estimator when that takes options.
    fn owner(&self) -> String {
        let e = self.estimator();
        if Estimator::option_keys(e.name()).is_some_and(|k| !k.is_empty()) {
            format!("{}\" with estimator \"{}", self.name(), e.name())
        } else {
            self.name().to_string()
        }
    }

    /// The table this description reads back from.
    pub fn to_table(&self) -> toml::Table {
        let mut t = toml::Table::new();
        t.insert("type".into(), self.name().into());
        self.write_params(&mut t);
        t
    }

    /// The integrator ready to render `world`.
    pub fn build(&self, world: &World) -> Result<IntegratorKind, SceneError> {
        let classified = world.media.iter().any(|m| m.medium.opacity.is_some());
        if classified && self.estimator() == Estimator::AnalyticTrilinear(AnalyticTrilinear) {
            return Err(SceneError(
                "integrator.estimator: analytic_trilinear integrates a trilinear field exactly, and a \
                 medium classified by a transfer function is not one; choose an unbiased estimator \
                 (ratio_tracking, track_length, …) or the transfer's mode = \"pre\""
                    .into(),
            ));
        }
        let caps = self.capabilities();
        if world.media.iter().any(|m| m.chroma.is_some()) && !caps.chromatic {
            return Err(SceneError(format!(
                "integrator.type: `{}` does not render chromatic extinction (sigma_t_scale = [r, g, b]); {} do",
                self.name(),
                IntegratorDesc::names_with(|c| c.chromatic).join(", ")
            )));
        }
        if !caps.far_clip && world.far_clip_cuts() {
            return Err(SceneError(format!(
                "camera.far_clip: the far plane cuts the scene, and `{}` does not end camera rays \
                 on it ({} do); move it beyond the scene",
                self.name(),
                IntegratorDesc::names_with(|c| c.far_clip).join(", ")
            )));
        }
        // restir, visopt, ament and point_mis see shapes as opaque black
        // occluders (shared/occluders.rs) and refuse the rest themselves.
        self.build_kind(world)
    }
}

impl<'de> serde::Deserialize<'de> for IntegratorDesc {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let table = toml::Table::deserialize(d)?;
        IntegratorDesc::from_table("integrator", table).map_err(serde::de::Error::custom)
    }
}

impl serde::Serialize for IntegratorDesc {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.to_table().serialize(s)
    }
}

impl IntegratorKind {
    /// What the user should know before rendering `world` with this
    /// integrator: shapes that it sees only as black occluders.
    pub fn notice(&self, world: &World) -> Option<String> {
        let s = world.surfaces.as_ref()?;
        self.integrator().occluders_only().then(|| {
            format!(
                "{} sees the scene's {} shape(s) as opaque black occluders: their BSDFs and emitters are not rendered (volpath renders them)",
                self.name(),
                s.shapes.len()
            )
        })
    }

    /// The transmittance estimator (for `volpath`: the NEE estimator);
    /// ratio tracking for the integrators that fix it (visopt, ament).
    pub fn estimator(&self) -> Estimator {
        self.integrator()
            .estimator()
            .unwrap_or(Estimator::RatioTracking(RatioTracking { roulette: 0.0 }))
    }

    pub fn estimator_name(&self) -> &'static str {
        self.estimator().name()
    }

    /// The same integrator with its transmittance estimator replaced (where
    /// it has one to replace).
    pub fn with_estimator(&self, e: Estimator) -> IntegratorKind {
        let mut k = self.clone();
        if let Some(estimator) = k.integrator_mut().estimator_mut() {
            *estimator = e;
        }
        k
    }

    /// Builds what the integrator gathers before its first sample (`volpath`'s
    /// pin grids, `visopt`'s camera lists), so a render's timer does not
    /// count it.
    pub fn prepare(&self, world: &World) {
        self.integrator().prepare(world);
    }
}

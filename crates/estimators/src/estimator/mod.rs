//! The estimator registry. Each estimator is one file in this folder: a
//! parameter struct implementing [`EstimatorPlugin`] (its name, what it
//! computes, its options and its transmittance along a ray, over the
//! algorithm in the crate's own module). One line of `estimators!` below
//! registers it: the line generates its variant of [`Estimator`], its place
//! in the listings and in the GPU's ids (`fogbank-gpu`'s `contract.rs`
//! numbers estimators by this order), its parsing and the per-ray dispatch.

pub mod options;
pub mod plugin;

pub use crate::estimate::Estimate;
pub use options::{OptionValue, Options};
pub use plugin::EstimatorPlugin;

use crate::roulette::DEFAULT_ROULETTE;
use fogbank_math::{Pcg32, Ray, RaySegment};
use fogbank_volume::Medium;

/// Declares each estimator's module, its variant of [`Estimator`] (holding
/// its parameter struct) and every listing and dispatch over them.
macro_rules! estimators {
    ($($(#[$attr:meta])* $variant:ident => $module:ident,)*) => {
        $(
            $(#[$attr])*
            pub mod $module;
            $(#[$attr])*
            pub use $module::$variant;
        )*

        /// A transmittance estimator with its options.
        #[derive(Clone, Copy, PartialEq)]
        pub enum Estimator {
            $($(#[$attr])* $variant($variant),)*
        }

        /// An estimator prints as its parameter struct
        /// (`Jackknife { samples: 20, … }`, `RegularTracking`).
        impl std::fmt::Debug for Estimator {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                match self {
                    $($(#[$attr])* Estimator::$variant(p) => p.fmt(f),)*
                }
            }
        }

        impl Estimator {
            /// Every estimator's name, in registry order.
            // Pushed one by one: an entry may be `#[cfg(test)]`, which a
            // `vec![…]` element cannot be.
            #[allow(clippy::vec_init_then_push)]
            pub fn names() -> Vec<&'static str> {
                let mut names = Vec::new();
                $(
                    $(#[$attr])*
                    names.push($variant::NAME);
                )*
                names
            }

            pub fn name(&self) -> &'static str {
                match self {
                    $($(#[$attr])* Estimator::$variant(_) => $variant::NAME,)*
                }
            }

            pub fn description(&self) -> &'static str {
                match self {
                    $($(#[$attr])* Estimator::$variant(_) => $variant::DESCRIPTION,)*
                }
            }

            pub fn biased(&self) -> bool {
                match self {
                    $($(#[$attr])* Estimator::$variant(_) => $variant::BIASED,)*
                }
            }

            /// Options and defaults, for `fogbank estimators`.
            pub fn options_help(&self) -> &'static str {
                match self {
                    $($(#[$attr])* Estimator::$variant(_) => $variant::OPTIONS_HELP,)*
                }
            }

            /// The option keys estimator `name` takes (`None`: no such estimator).
            pub fn option_keys(name: &str) -> Option<&'static [&'static str]> {
                match name {
                    $($(#[$attr])* n if n == $variant::NAME => Some($variant::KEYS),)*
                    _ => None,
                }
            }

            /// The options that give this estimator back through
            /// [`Estimator::with_options`] (every option it takes, spelled out).
            pub fn options(&self) -> Options {
                match self {
                    $($(#[$attr])* Estimator::$variant(p) => p.options(),)*
                }
            }

            /// Estimator `name` read from `o` (only keys it takes); `None`
            /// for no such estimator.
            fn read(name: &str, o: &Options) -> Option<Result<Estimator, String>> {
                match name {
                    $($(#[$attr])* n if n == $variant::NAME => {
                        Some($variant::read(o).map(Estimator::$variant))
                    })*
                    _ => None,
                }
            }

            fn transmittance_along(
                &self,
                view: fogbank_volume::MediumView<'_>,
                seg: &RaySegment,
                rng: &mut Pcg32,
            ) -> Estimate {
                match self {
                    $($(#[$attr])* Estimator::$variant(p) => p.transmittance(view, seg, rng),)*
                }
            }
        }
    };
}

estimators! {
    RegularTracking => regular_tracking,
    AnalyticTrilinear => analytic_trilinear,
    TrackLength => track_length,
    RatioTracking => ratio_tracking,
    ResidualRatioTracking => residual_ratio_tracking,
    RayMarching => ray_marching,
    BiasedRayMarching => biased_ray_marching,
    UnbiasedRayMarching => unbiased_ray_marching,
    Jackknife => jackknife,
    JackknifeNaive => jackknife_naive,
    JackknifeMeanImportance => jackknife_mean_importance,
    #[cfg(test)]
    TestHalf => test_half,
}

/// The estimator a scene gets when it names none: ratio tracking with its
/// default roulette (as pbrt-v4's and Mitsuba 3's shadow rays, unbiased
/// and bounded in cost however dense the medium).
impl Default for Estimator {
    fn default() -> Self {
        Estimator::RatioTracking(RatioTracking {
            roulette: DEFAULT_ROULETTE,
        })
    }
}

impl Estimator {
    /// Every estimator with default options.
    pub fn all() -> Vec<Estimator> {
        Estimator::names()
            .into_iter()
            .map(|n| Estimator::parse(n).expect("registered names parse"))
            .collect()
    }

    /// An estimator from the command line: `NAME` or `NAME:KEY=VALUE:…`
    /// (`ratio_tracking:roulette=0.1`, `jackknife:samples=20:jitter=uniform`).
    pub fn parse_spec(spec: &str) -> Result<Estimator, String> {
        let (name, options) = spec.split_once(':').unwrap_or((spec, ""));
        let mut o = Options::default();
        for kv in options.split(':').filter(|s| !s.trim().is_empty()) {
            let (k, v) = kv
                .split_once('=')
                .ok_or_else(|| format!("`{spec}`: expected KEY=VALUE, got `{kv}`"))?;
            o.set(k.trim(), OptionValue::from_text(v.trim()));
        }
        Estimator::with_options(name, &o).map_err(|e| format!("`{spec}`: {e}"))
    }

    /// The same estimator with Russian roulette off: the plain ratio and
    /// residual ratio tracking that Peters 2025's studies compare; every other
    /// estimator unchanged.
    pub fn without_roulette(self) -> Estimator {
        match self {
            Estimator::RatioTracking(_) => {
                Estimator::RatioTracking(RatioTracking { roulette: 0.0 })
            }
            Estimator::ResidualRatioTracking(_) => {
                Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette: 0.0 })
            }
            e => e,
        }
    }

    /// The estimator `name` with default options.
    pub fn parse(name: &str) -> Option<Estimator> {
        Estimator::with_options(name, &Options::default()).ok()
    }

    /// The estimator `name` with `o` applied; an option the estimator does
    /// not take, or a bad value, is an error naming it.
    pub fn with_options(name: &str, o: &Options) -> Result<Estimator, String> {
        let unknown = || {
            format!(
                "unknown estimator `{name}` (available: {})",
                Estimator::names().join(", ")
            )
        };
        let allowed = Estimator::option_keys(name).ok_or_else(unknown)?;
        if let Some((bad, _)) = o.iter().find(|(k, _)| !allowed.contains(k)) {
            return Err(format!("estimator `{name}` has no option `{bad}`"));
        }
        Estimator::read(name, o).unwrap_or_else(|| Err(unknown()))
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
    let Some((r, t0, t1)) = medium.to_index(world, 0.0, t_max) else {
        return Estimate::ONE;
    };
    e.transmittance_along(medium.view(), &RaySegment::new(r, t0, t1), rng)
}

#[cfg(test)]
mod estimator_test {
    use super::*;
    use crate::jackknife::StepMode;
    use crate::optical_depth::Jitter;

    #[test]
    fn specs_give_options_and_refuse_what_an_estimator_lacks() {
        assert_eq!(
            Estimator::parse_spec("ratio_tracking:roulette=0.1"),
            Ok(Estimator::RatioTracking(RatioTracking { roulette: 0.1 }))
        );
        assert_eq!(
            Estimator::parse_spec("residual_ratio_tracking:roulette=0"),
            Ok(Estimator::ResidualRatioTracking(ResidualRatioTracking {
                roulette: 0.0
            }))
        );
        assert_eq!(
            Estimator::parse_spec("jackknife:samples=20:jitter=uniform"),
            Ok(Estimator::Jackknife(Jackknife {
                samples: 20,
                mode: StepMode::FixedCount,
                jitter: Jitter::Uniform
            }))
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
        // Options survive the round trip through Options.
        let e = Estimator::RatioTracking(RatioTracking { roulette: 0.25 });
        assert_eq!(Estimator::with_options(e.name(), &e.options()), Ok(e));
    }

    /// The test-only estimator, registered in its one line, is listed,
    /// parsed with its option, written back and dispatched per ray.
    #[test]
    fn a_registered_estimator_is_listed_parsed_and_dispatched() {
        assert_eq!(Estimator::names().last(), Some(&"test_half"));
        let e = Estimator::parse_spec("test_half:level=0.25").unwrap();
        assert_eq!(e, Estimator::TestHalf(TestHalf { level: 0.25 }));
        assert_eq!(Estimator::with_options(e.name(), &e.options()), Ok(e));
        assert!(Estimator::parse_spec("test_half:samples=3").is_err());
        assert_eq!(Estimator::option_keys("test_half"), Some(&["level"][..]));
        let g = fogbank_volume::BrickGrid::from_fn([4, 4, 4], |_, _, _| 1.0).unwrap();
        let data = fogbank_volume::DensityData::from_f32(g, fogbank_volume::Precision::F32);
        let filter = fogbank_volume::Filter::Trilinear;
        let medium = Medium::new(data, 1.0, filter, Default::default(), 4);
        let ray = Ray::new(
            fogbank_math::Vec3::new(0.0, 0.0, -5.0),
            fogbank_math::Vec3::Z,
        );
        let t = transmittance(e, &medium, &ray, 10.0, &mut Pcg32::new(1, 1));
        assert_eq!(t.transmittance, 0.25);
        assert!(Estimator::all().contains(&Estimator::TestHalf(TestHalf { level: 0.5 })));
    }

    /// Both trackers play roulette unless told not to, and `fogbank
    /// estimators` states the default the parser uses.
    #[test]
    fn trackers_play_roulette_by_default() {
        const { assert!(DEFAULT_ROULETTE > 0.0) };
        for name in ["ratio_tracking", "residual_ratio_tracking"] {
            let e = Estimator::parse(name).unwrap();
            assert_eq!(
                e.options().get("roulette"),
                Some(&OptionValue::Float(DEFAULT_ROULETTE as f64)),
                "{name}"
            );
            let said = format!("roulette={DEFAULT_ROULETTE} ");
            assert!(
                e.options_help().starts_with(&said),
                "{name}: {}",
                e.options_help()
            );
            assert_eq!(
                e.without_roulette().options().get("roulette"),
                Some(&OptionValue::Float(0.0))
            );
        }
        let j = Estimator::parse("jackknife").unwrap();
        assert_eq!(j.without_roulette(), j);
    }
}

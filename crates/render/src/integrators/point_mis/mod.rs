//! `point_mis`: single scattering from point lights inside one medium,
//! with the distance-sampling strategies of Peters 2025 §5 and §6.2 (Fig. 12).
//!
//! Per camera sample one point light is chosen in proportion to its power
//! ([`LightSampler`]; for point lights 4π·luminance(I)) and both distance
//! samples of the MIS strategies estimate the single-scattering integral of
//! that light (Peters 2025 Eq. 2 truncated to one bounce),
//!
//! ```text
//! L = ∫_a^b T(t) μ(t) L_s(t) dt,   L_s(t) = α ρ(cos θ) I T_l(t) / d(t)²,
//! ```
//!
//! divided by the light's selection probability. `T_l`, the transmittance
//! from the scattering point to the light, uses the integrator's `estimator`
//! (Peters 2025 Fig. 12 uses the jackknife there). Where a strategy needs T(t0)
//! along the camera ray at an equiangular sample it uses ratio tracking, the
//! unbiased estimator that §5.2 asks for and that Miller et al.'s MIS reuses.
//! The MIS strategies take two distance samples per pixel sample (the paper
//! counts "16 spp, but for MIS that amounts to 32 distance samples").
//!
//! Only point lights and exactly one medium are supported: the free-flight
//! pdf T(t)μ(t) of overlapping media would need the summed extinction in
//! every optical-depth estimate; [`settings`] rejects other scenes. Shapes
//! are opaque black occluders (`shared/occluders.rs`): the camera segment
//! ends at the first surface and light rays a surface cuts carry nothing.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `strategy` | mis_jackknife | `free_flight`, `equiangular`, `mis_miller` (ratio-tracking weights from delta tracking's null collisions, Miller et al. 2019), `mis_naive` (Eq. 10 with g(X), m = 1; biased), `mis_jackknife` (Eq. 9, jackknife weights, unbiased), `mis_jackknife_biased` (Eq. 10) |
//! | `estimator` | ratio_tracking (roulette 0.03) | transmittance estimator of the light ray (`fogbank estimators`), with its options |
//! | `mis_samples` | 10 | lookups N per optical-depth estimate of the MIS weights (1..=4096) |

pub mod analysis;
pub mod integrator;
pub mod params;
pub mod strategy;

pub use analysis::jackknife_weights;
pub use integrator::PointMis;
pub use params::{PointMisParams, DEFAULT_MIS_SAMPLES, PARAMS};
pub use strategy::Strategy;

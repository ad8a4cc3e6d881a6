//! Transmittance and optical-depth estimators of fogbank.
//!
//! Every estimator is a plain function generic over
//! [`fogbank_volume::VolumeAccess`], so the hot loop is monomorphised per
//! storage type and has no dynamic dispatch; [`transmittance`] matches the
//! medium's storage once per ray. All estimators count full-resolution
//! lookups (filtered evaluations of σ_t) in [`Estimate::lookups`].
//!
//! # Glossary
//!
//! One name per quantity in Rust and WGSL alike; the seeds write some of
//! them differently.
//!
//! | name | quantity | Peters 2025 | Lin et al. 2021 | Hansen 2025 | pbrt-v4 |
//! |---|---|---|---|---|---|
//! | `sigma_t` | extinction coefficient (per world unit; per index unit inside estimators) | μ(t) | σ_t | σ_t, μ | `sigma_t` |
//! | `sigma_t_at` | σ_t at a point: one filtered lookup, counted | μ(x) | | | `SampleT_maj` callback |
//! | `LookupBatch` | lookups of a fixed-count estimator queued and read eight at a time (SIMD lanes), bit for bit `sigma_t_at` in order | | | | |
//! | `sigma_maj` | majorant, per super-voxel the maximum of σ_t | μ̄ | σ̄ | μ̄ | `sigma_maj` |
//! | `sigma_min` | minorant, per super-voxel the minimum of σ_t | μ_min | | | |
//! | `sigma_c` | control extinction (residual ratio tracking, the Eq. 5 control variate) | μ_c | σ_c | | |
//! | `sigma_r` | majorant of the residual σ_t − σ_c | | | | |
//! | `tau` | optical depth ∫ σ_t dt | τ, X (its estimate) | τ | τ | |
//! | `transmittance`, `tr` | T = exp(−τ) | T | T | T | `T_maj` ratio |
//! | `importance` | Peters 2025 Eq. 5 sampling density of the lookups | p(t) | | | |
//! | `albedo` | σ_s / σ_t | α | ρ | α | |
//!
//! In Peters 2025's 1D experiments (`fogbank-eval`), `Profile1D::sigma_t_at`
//! is μ(t) of the paper's figures (their axis labels keep the paper's μ).
//!
//! # Modules
//!
//! In layers, each importing only those before it:
//!
//! - `estimate` (what one estimate returns), `lookup` (the one place estimators read the
//!   volume: counts the lookup, draws the stochastic-filter jitter), `roulette` (Russian
//!   roulette on a tracking walk's running weight), `jackknife_function` (jackknife
//!   estimates of functions of τ, Peters 2025 §5.1: Eq. 7, App. F's MIS weights, Eq. 3's
//!   UMVU estimate of e^{−τ}) and the deterministic integrals: `regular_tracking`
//!   (Szirmay-Kalos et al. 2010, Peters 2025 §2.1: exact τ of the nearest-filtered grid
//!   along a DDA), `analytic_trilinear` (exact τ of the trilinear interpolant, Lin et al. 2021
//!   §5) and `deterministic_marching` (the reuse target's T̃, Lin et al. 2021 §4.3, §5.1);
//! - `null_collisions` (the tentative-collision process of the tracking estimators),
//!   `optical_depth` (importance-sampled ray-marching estimates of τ, Peters 2025 Algs. 1
//!   and 2) and `pins` (pin transmittance sampling, Hansen 2025, Hansen 2025);
//! - `ratio_tracking` (Novák et al. 2014, Peters 2025 §2.2), `residual_ratio_tracking`
//!   (Novák et al. 2014: a per-super-voxel control extinction plus ratio tracking of the
//!   residual), `jackknife` (Peters 2025's jackknife transmittance, Eqs. 4 and 5, and its
//!   ablations), `kettunen` (Kettunen et al. 2021's biased and unbiased ray-marching
//!   estimators) and `ray_marching` (naive ray marching, T = exp(−X), biased);
//! - `distance` (distance samplers: delta, decomposition and regular tracking, and the
//!   equiangular sampler) → `track_length` (Peters 2025 §2.2: delta tracking's 0/1 estimate);
//! - `estimator/` (the registry: one file per estimator, a parameter struct implementing
//!   `EstimatorPlugin` — name, description, options, per-ray transmittance — registered
//!   in one line of `estimators!`, which generates the `Estimator` enum, listings, parsing
//!   and dispatch) →
//!   `scaled` (transmittances of several extinctions k_c · σ_t from one walk, for
//!   chromatic media with one density).

/// Expands `body` once per storage type with `v` bound to the typed view, so
/// each estimator is monomorphised and the match happens once per ray.
macro_rules! with_view {
    ($view:expr, $v:ident => $body:expr) => {
        match $view {
            MediumView::F16($v) => $body,
            MediumView::F32($v) => $body,
            MediumView::Analytic($v) => $body,
        }
    };
}

pub mod analytic_trilinear;
pub mod deterministic_marching;
pub mod distance;
pub mod estimate;
pub mod estimator;
pub mod jackknife;
pub mod jackknife_function;
pub mod kettunen;
pub mod lookup;
pub mod null_collisions;
pub mod optical_depth;
pub mod pins;
pub mod ratio_tracking;
pub mod ray_marching;
pub mod regular_tracking;
pub mod residual_ratio_tracking;
pub mod roulette;
pub mod scaled;
pub mod track_length;

pub use estimate::Estimate;
pub use estimator::{transmittance, Estimator, EstimatorPlugin, OptionValue, Options};

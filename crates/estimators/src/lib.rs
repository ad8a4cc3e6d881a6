//! Transmittance and optical-depth estimators of fogbank.
//!
//! Every estimator is a plain function generic over
//! [`fogbank_volume::VolumeAccess`], so the hot loop is monomorphised per
//! storage type and has no dynamic dispatch; [`transmittance`] matches the
//! medium's storage once per ray. All estimators count full-resolution
//! lookups (filtered evaluations of σ_t) in [`Estimate::lookups`].

pub mod analytic_trilinear;
pub mod distance;
pub mod estimate;
pub mod estimator;
pub mod jackknife;
pub mod jackknife_function;
pub mod kettunen;
pub mod lookup;
pub mod null_collisions;
pub mod optical_depth;
pub mod ratio_tracking;
pub mod ray_marching;
pub mod regular_tracking;
pub mod residual_ratio_tracking;
pub mod track_length;

pub use estimate::Estimate;
pub use estimator::{transmittance, Estimator, EstimatorOptions};

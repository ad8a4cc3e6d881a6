//! `fogbank-estimators`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod support;

mod deterministic_marching;
mod distance;
mod empty_space;
mod exact;
mod guide;
mod jackknife;
mod pins;
mod ray_marching_step;
mod tracking_lanes;
mod unbiased;

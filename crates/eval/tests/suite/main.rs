//! `fogbank-eval`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod experiments;
mod frame_stats;
mod integrator_consistency;
mod jackknife_ordering;
mod pins_volpath;
mod restir_unbiased;

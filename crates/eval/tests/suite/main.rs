//! `fogbank-eval`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod frame_stats;
mod jackknife_ordering;

//! `fogbank-image`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod metrics_basic;
mod metrics_flip;
mod metrics_io;
mod metrics_ztest;

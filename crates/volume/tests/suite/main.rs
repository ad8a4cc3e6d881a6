//! `fogbank-volume`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod support;

mod bc4;
mod mip;
mod nanovdb;
mod nanovdb_robustness;
mod nanovdb_write;
mod sci_loaders;
mod vdb_read;
mod vdb_robustness;
mod vdb_write;

//! `fogbank-geometry`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod bvh;

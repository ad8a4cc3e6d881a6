//! `fogbank-gpu`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod support;

mod bvh_gpu;
mod mitsuba_gpu;
mod pins_gpu;
mod restir_gpu;
mod scatter_gpu;
mod transfer_gpu;
mod transmittance_gpu;
mod visopt_gpu;

//! `fogbank-experiments`' integration tests, one module per concept, in one
//! binary: the papers' experiments at reduced trial counts, and the
//! integrators' agreement measured with the experiments' rendering protocol.

mod experiments;
mod integrator_consistency;
mod pins_volpath;
mod restir_unbiased;

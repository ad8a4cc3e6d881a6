//! `fogbank-scene`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod support;

mod convert;
mod export;
mod light_selection;
mod load;
mod mitsuba;
mod mitsuba_reader;
mod pbrt;
mod pbrt_mitsuba;
mod pbrt_scenes;
mod shape_instances;

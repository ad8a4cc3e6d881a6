//! `fogbank-render`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod support;

mod ament;
mod animation;
mod bsdf;
mod chroma;
mod determinism;
mod direct;
mod envmap;
mod format_table;
mod instances;
mod lights;
mod nanovdb_render;
mod occluders;
mod param_tables;
mod phase;
mod pin_stream;
mod point_mis;
mod reservoir;
mod restir;
mod scene;
mod sci_placement;
mod surfaces;
mod transfer;
mod visopt;
mod volpath;

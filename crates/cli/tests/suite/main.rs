//! `fogbank-cli`'s integration tests, one module per concept, in one
//! binary: one compile and link for the crate's whole suite.

mod support;

mod cli;
mod convert_cli;
mod crate_layers;
mod export_cli;
mod external_paths;
mod help;
mod kubernetes;
mod module_cycles;
mod python;
mod scenes;
mod shard_cli;
mod slurm;
mod viewer;

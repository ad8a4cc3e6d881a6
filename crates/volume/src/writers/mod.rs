//! Volume writers: OpenVDB (`.vdb`, [`vdb`]) and NanoVDB (`.nvdb`,
//! [`nanovdb`]) files from the sparse grid the readers return
//! ([`VdbGrid`](crate::loaders::vdb::VdbGrid)), and the conversion of
//! fogbank's brick grids back to that grid ([`from_brick_grid`]).
//!
//! Both writers build the whole file in memory first: the formats store
//! offsets and sizes ahead of the data they describe.

mod bricks;
mod bytes;
mod compress;
pub mod nanovdb;
mod nanovdb_grid;
mod nanovdb_map;
mod nanovdb_quantise;
mod nanovdb_stats;
mod options;
mod tree;
pub mod vdb;

pub use bricks::{from_brick_grid, rows, VDB_FILE_VERSION};
pub use nanovdb::NanoOptions;
pub use options::{Codec, NanoValue};
pub use vdb::VdbOptions;

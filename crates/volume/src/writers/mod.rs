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
mod tree;
pub mod vdb;

pub use bricks::{from_brick_grid, rows, VDB_FILE_VERSION};
pub use nanovdb::{NanoOptions, NanoValue};
pub use vdb::VdbOptions;

/// How a file's data is compressed: OpenVDB compresses each node buffer,
/// NanoVDB each grid buffer, with zlib (Zip) or Blosc (LZ4 frames).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Codec {
    #[default]
    None,
    Zip,
    Blosc,
}

impl Codec {
    pub fn name(self) -> &'static str {
        match self {
            Codec::None => "none",
            Codec::Zip => "zip",
            Codec::Blosc => "blosc",
        }
    }

    /// `none`, `zip` or `blosc`.
    pub fn parse(s: &str) -> Option<Codec> {
        match s {
            "none" => Some(Codec::None),
            "zip" => Some(Codec::Zip),
            "blosc" => Some(Codec::Blosc),
            _ => None,
        }
    }
}

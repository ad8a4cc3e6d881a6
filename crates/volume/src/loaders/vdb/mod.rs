//! OpenVDB (`.vdb`) reader for float grids, and for `vec3s` (velocity) grids
//! as three float grids, one per component.
//!
//! Our own parser rather than a binding or the `vdb-rs` crate: that crate
//! aborts on half-float compressed grids and rejects affine transforms, and
//! a renderer must survive whatever file a user hands it. Every count and
//! size read from the file is checked against the bytes that remain before
//! anything is allocated, and decompressed sizes are capped by what the node
//! needs, so malformed input yields a [`VolumeError`](crate::VolumeError) naming the file, the
//! grid and the byte offset, never a panic or a huge allocation.
//!
//! | feature | supported |
//! |---|---|
//! | file format versions | 222 – 225 (224 is what Houdini 17+ and OpenVDB 6 – 11 write); older and newer versions are rejected with a clear error |
//! | grid value types | `float` ([`read_grid`]) and `vec3s` ([`read_vec3_grid`]) with the standard 5-4-3 tree; other types (`vec3d`, `vec3i`, `bool`, …) are listed (`supported = false`) and rejected with an error naming the type |
//! | storage | float32, half float (`_HalfFloat` grids: node values half; background, root tiles and per-node inactive values full width) |
//! | compression | none, Zip (zlib), Blosc (blosclz, lz4, lz4hc, zlib codecs; byte and bit shuffle), active-mask (all 7 per-node modes) |
//! | Blosc codecs snappy, zstd | no (clear error) |
//! | transforms | UniformScale, UniformScaleTranslate, Scale, ScaleTranslate, Translation, Affine, Unitary maps; frustum and other non-linear maps are rejected |
//! | tree | root, internal (32³, 16³) and leaf nodes; constant tiles at every level, active or inactive |
//! | several grids per file | yes; selected by name (`name`, or `name[N]` for duplicated names) using the stored grid offsets |
//! | instanced grids | yes (the tree is read from the instance parent) |
//! | files without grid offsets (streams) | yes, as long as every grid before the wanted one is a float or `vec3s` grid |
//! | large files | read whole up to 64 MiB; beyond that only the header, the descriptors and the chosen grid's bytes are read |
//! | delayed-load metadata, multi-pass (point) grids | ignored / not supported |

pub mod blosc;
pub(crate) mod format;
mod grid;
mod header;
mod metadata;
mod read;
mod reader;
mod transform;
mod tree;
mod values;

pub(crate) use grid::Tile;
pub use grid::{GridClass, VdbGrid, VdbGridDescriptor, VdbLeaf, VdbTile};
pub use read::{
    list_grids, list_grids_from_bytes, parse_grid, parse_vec3_grid, read_grid, read_vec3_grid,
};

//! NanoVDB (`.nvdb`) reader for float grids (full precision, double and
//! the quantised Fp4/Fp8/Fp16/FpN leaves), and for `Vec3f`/`Vec3d`
//! (velocity) grids as three float grids, one per component.
//!
//! It returns the same [`VdbGrid`](super::vdb::VdbGrid) as the OpenVDB reader, so a NanoVDB file
//! feeds every estimator, integrator and tool that an OpenVDB file does.
//!
//! The layout it reads is NanoVDB's (`NanoVDB.h` and `util/IO.h`, ABI major
//! version 32):
//!
//! - a file is a sequence of segments: a 16-byte header (magic `NanoVDB0`,
//!   version, grid count, codec), one 176-byte metadata record plus name per
//!   grid, then each grid's bytes, raw, zlib-compressed (`u64` size + one
//!   stream) or Blosc-compressed (`u64` size + one Blosc1 frame per GiB);
//! - a grid buffer is `GridData` (672 B: magic, checksum, version, flags,
//!   size, name, the index↔world `Map` in f32 and f64, class, type), then
//!   `TreeData` (64 B: byte offsets to the first node of each level and node
//!   counts), the root (background, a table of tiles keyed by origin, each a
//!   value or a child offset), the 32³ upper and 16³ lower internal nodes
//!   (value and child masks, a table of values or child offsets) and the 8³
//!   leaves; every structure is 32-byte aligned and every child is reached
//!   through a signed byte offset from its parent.
//!
//! Every offset, count and size read from the file is checked against the
//! bytes that hold it before anything is read or allocated, nodes may be
//! reached only once and no more often than the tree's node counts say, and
//! decompression stops at the size the metadata declares; malformed input
//! yields a [`VolumeError`](crate::VolumeError) naming the file, the grid
//! and the byte offset, never a panic.
//!
//! | feature | supported |
//! |---|---|
//! | versions | major 32 (checked against files of NanoVDB 32.4, OpenVDB 10); other majors are rejected with a clear error |
//! | value types | `float`, `double` (rounded to f32), `Fp4`, `Fp8`, `Fp16`, `FpN` (value = code · quantum + minimum, as NanoVDB computes it), `Vec3f` and `Vec3d` ([`read_vec3_grid`]); others (`Half`, which NanoVDB only reserves, integers, masks, index grids) are listed and rejected with an error naming the type |
//! | codecs | none, ZIP (zlib), BLOSC (Blosc1 frames, any codec the OpenVDB reader's Blosc decoder reads) |
//! | grid classes | fog volume, level set, staggered; others read as unknown |
//! | several grids and segments per file | yes; selected by name (default `density`, else the first float grid) |
//! | checksum | verified (partial and full CRC32) for NanoVDB 32.4 grids; grids of other minor versions are read without it |
//! | raw grid buffers (no segment header, 32.6+) | yes (`NanoVDB1` grid magic, or `NanoVDB0` with the version where a grid has it); tested with 32.4 grids stored that way, no 32.6 writer at hand |
//! | large files | only the segment headers and the chosen grid's bytes are read, front to back: the internal nodes in front of the first leaf are held, the leaves stream past a run at a time (ZIP inflated and BLOSC frames decoded block by block as they are read); [`read_grid_bricks`] stores each leaf in fogbank's brick grid as it passes, so loading peaks at about 1.3× the grid it makes |

mod checksum;
mod gridbuf;
mod griddata;
pub(crate) mod layout;
mod leaf;
mod leaves;
mod read;
mod segment;
mod stream;
mod tree;

pub use read::{
    list_grids, list_grids_from_bytes, read_grid, read_grid_bricks, read_grid_from_bytes,
    read_vec3_grid, read_vec3_grid_from_bytes,
};
pub use segment::version_string;

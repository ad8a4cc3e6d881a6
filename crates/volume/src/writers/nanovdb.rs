//! NanoVDB (`.nvdb`) writer: float grids as `Float`, `Fp8` or `Fp16`
//! values, in NanoVDB 32.4.2's layout (what Debian's `nanovdb_print`,
//! `nanovdb_validate` and `nanovdb_convert` of OpenVDB 10 read), stored
//! raw, ZIP or BLOSC compressed (`util/IO.h`).
//!
//! A file is one segment per grid, as `nanovdb_convert` writes it: a
//! 16-byte header (magic `NanoVDB0`, version, grid count 1, codec), the
//! grid's 176-byte metadata record (buffer and stored sizes, name hash,
//! active voxel count, type, class, world and index boxes, voxel size,
//! name length, node and tile counts, codec, version) and its name, then
//! the grid's bytes: the buffer as is; for ZIP, a `u64` size and one zlib
//! stream; for BLOSC, chunks of at most 2³⁰ bytes, each a `u64` size and
//! one Blosc1 frame. The grid buffer itself is built by `nanovdb_grid`.

use std::io::Write;
use std::path::Path;

use super::bytes::Put;
use super::compress::{blosc, zlib};
use super::nanovdb_grid::{build, GridBuffer, MAGIC, VERSION};
use super::options::{Codec, NanoValue};
use crate::loaders::vdb::VdbGrid;
use crate::{Result, VolumeError};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NanoOptions {
    pub value: NanoValue,
    pub codec: Codec,
}

/// NanoVDB cuts BLOSC input into chunks of this size.
const BLOSC_CHUNK: usize = 1 << 30;
const META_LEN: usize = 176;

/// Writes `grids` to the file `path`.
pub fn write(path: &Path, grids: &[VdbGrid], options: NanoOptions) -> Result<()> {
    let bytes = to_bytes(grids, options)?;
    std::fs::write(path, bytes).map_err(|e| VolumeError::io(path, e))
}

/// Writes `grids` as one `.nvdb` file to `w`.
pub fn write_to(w: &mut impl Write, grids: &[VdbGrid], options: NanoOptions) -> Result<()> {
    let bytes = to_bytes(grids, options)?;
    w.write_all(&bytes)
        .map_err(|e| VolumeError::io(Path::new("<stream>"), e))
}

/// The `.nvdb` file of `grids`.
pub fn to_bytes(grids: &[VdbGrid], options: NanoOptions) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    for g in grids {
        let grid = build(g, options.value)?;
        let stored = encode(&grid.bytes, options.codec)?;
        out.u64(MAGIC);
        out.u32(VERSION);
        out.extend_from_slice(&1u16.to_le_bytes());
        out.extend_from_slice(&codec_code(options.codec).to_le_bytes());
        write_meta(&mut out, g, &grid, stored.len() as u64, options.codec);
        out.extend_from_slice(&stored);
    }
    Ok(out)
}

fn codec_code(c: Codec) -> u16 {
    match c {
        Codec::None => 0,
        Codec::Zip => 1,
        Codec::Blosc => 2,
    }
}

/// The grid's bytes as the codec stores them.
fn encode(buffer: &[u8], codec: Codec) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    match codec {
        Codec::None => out.extend_from_slice(buffer),
        Codec::Zip => {
            let z = zlib(buffer);
            out.u64(z.len() as u64);
            out.extend_from_slice(&z);
        }
        Codec::Blosc => {
            for chunk in buffer.chunks(BLOSC_CHUNK) {
                let frame = blosc(chunk, 4).ok_or_else(|| {
                    VolumeError::Invalid("grid chunk too large for a Blosc frame".into())
                })?;
                out.u64(frame.len() as u64);
                out.extend_from_slice(&frame);
            }
        }
    }
    Ok(out)
}

/// NanoVDB's name hash (`io::stringHash`), stored with the metadata.
fn name_key(name: &str) -> u64 {
    name.bytes().fold(0u64, |h, c| {
        let overflow = h >> 56;
        h.wrapping_mul(67).wrapping_add(c as u64 + overflow)
    })
}

/// One `io::MetaData` record and the NUL-terminated name.
fn write_meta(out: &mut Vec<u8>, g: &VdbGrid, grid: &GridBuffer, stored: u64, codec: Codec) {
    let start = out.len();
    out.u64(grid.bytes.len() as u64);
    out.u64(stored);
    out.u64(name_key(&g.name));
    out.u64(grid.voxel_count);
    out.u32(grid.grid_type);
    out.u32(grid.grid_class);
    for v in grid.world_bbox {
        out.f64(v);
    }
    for v in grid.index_bbox {
        out.i32(v);
    }
    for v in grid.voxel_size {
        out.f64(v);
    }
    out.u32(g.name.len() as u32 + 1);
    for c in grid.node_count {
        out.u32(c);
    }
    out.u32(1); // one root
    for c in grid.tile_count {
        out.u32(c);
    }
    out.extend_from_slice(&codec_code(codec).to_le_bytes());
    out.extend_from_slice(&[0, 0]);
    out.u32(VERSION);
    debug_assert_eq!(out.len() - start, META_LEN);
    out.extend_from_slice(g.name.as_bytes());
    out.u8(0);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn name_key_matches_nanovdb() {
        // As `nanovdb_convert` stored it for `ls_cube`.
        assert_eq!(name_key("ls_cube"), 0x9073e47f9dd);
    }
}

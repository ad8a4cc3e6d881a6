//! OpenVDB (`.vdb`) writer for float grids: file format version 224 (what
//! OpenVDB 6 – 11 write), the standard 5-4-3 tree, values stored as float
//! or half (`_HalfFloat` grids), node buffers raw, Zip (zlib) or Blosc
//! compressed.
//!
//! It writes what the reader (`loaders/vdb`) reads, following OpenVDB's
//! `io::File`/`io::Archive` layout:
//!
//! - header: magic, file version, library version, "has grid offsets" flag,
//!   a 36-character UUID, the file's metadata map and the grid count;
//! - per grid: its descriptor (unique name, tree type, instance parent, and
//!   the grid's start, buffer start and end offsets), the grid's
//!   compression flags, metadata (its `class`), transform map, then the
//!   tree: its topology (root background, tiles and children; each
//!   internal node's child mask, value mask and tile values, depth first;
//!   each leaf's value mask), then every leaf's buffer in the same order.
//!
//! Every node value buffer starts with a per-node byte saying how inactive
//! values were stored. Without active-mask compression every buffer holds
//! all its values (indicator 6, "no mask and all values"); with it, a node
//! whose inactive values are all the background (or its negation) holds
//! only its active values, and any other node all of them (OpenVDB's
//! selection-mask modes are not written). A Zip or Blosc buffer is an
//! `i64` size and the compressed bytes, or the negated size and the raw
//! bytes when compression does not pay off, as OpenVDB writes them.
//!
//! The transform is a `UniformScaleTranslateMap` when the index→world map
//! is a uniform scale and a translation, else an `AffineMap`.

use std::io::Write;
use std::path::Path;

use super::bytes::{put_at, Put};
use super::compress::{blosc, zlib};
use super::options::Codec;
use super::tree::{child_origin, Internal, RootEntry, TileValue, Tree};
use crate::loaders::vdb::format::{COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC, COMPRESS_ZIP};
use crate::loaders::vdb::format::{FLOAT_TREE, HALF_SUFFIX, MAGIC, NAME_SEP};
use crate::loaders::vdb::format::{
    NO_MASK_AND_ALL_VALS, NO_MASK_AND_MINUS_BG, NO_MASK_OR_INACTIVE_VALS,
};
use crate::loaders::vdb::{VdbGrid, VdbLeaf};
use crate::{Result, VolumeError};

const FILE_VERSION: u32 = super::bricks::VDB_FILE_VERSION;
/// The OpenVDB library version the file claims to come from (10.0, whose
/// file format is 224).
const LIBRARY_VERSION: [u32; 2] = [10, 0];

/// How float values are stored and compressed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct VdbOptions {
    /// Store node values as half floats (`_HalfFloat`); background and
    /// tile values stay full width, as OpenVDB keeps them.
    pub half: bool,
    pub codec: Codec,
    /// Active-mask compression: nodes whose inactive values are all the
    /// background (or its negation) store only their active values.
    pub active_mask: bool,
}

/// Writes `grids` to the file `path`.
pub fn write(path: &Path, grids: &[VdbGrid], options: VdbOptions) -> Result<()> {
    let bytes = to_bytes(grids, options)?;
    std::fs::write(path, bytes).map_err(|e| VolumeError::io(path, e))
}

/// Writes `grids` as one `.vdb` file to `w`.
pub fn write_to(w: &mut impl Write, grids: &[VdbGrid], options: VdbOptions) -> Result<()> {
    let bytes = to_bytes(grids, options)?;
    w.write_all(&bytes)
        .map_err(|e| VolumeError::io(Path::new("<stream>"), e))
}

/// The `.vdb` file of `grids`.
pub fn to_bytes(grids: &[VdbGrid], options: VdbOptions) -> Result<Vec<u8>> {
    let count = i32::try_from(grids.len())
        .map_err(|_| VolumeError::Invalid(format!("{} grids are too many", grids.len())))?;
    let mut out = Vec::new();
    out.extend_from_slice(&MAGIC);
    out.u32(FILE_VERSION);
    out.u32(LIBRARY_VERSION[0]);
    out.u32(LIBRARY_VERSION[1]);
    out.u8(1); // grid offsets follow each descriptor
    out.extend_from_slice(uuid(grids).as_bytes());
    out.u32(0); // no file metadata
    out.i32(count);
    let names = unique_names(grids)?;
    for (g, name) in grids.iter().zip(&names) {
        write_grid(&mut out, g, name, options)?;
    }
    Ok(out)
}

/// Names as OpenVDB stores them: a name used more than once gets its index
/// among the grids of that name after a `\x1e`.
fn unique_names(grids: &[VdbGrid]) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for (i, g) in grids.iter().enumerate() {
        if g.name.contains(NAME_SEP) {
            return Err(VolumeError::Invalid(format!(
                "grid name {:?} contains the reserved character \\x1e",
                g.name
            )));
        }
        let before = grids[..i].iter().filter(|h| h.name == g.name).count();
        let dup = grids.iter().filter(|h| h.name == g.name).count() > 1;
        out.push(match dup {
            true => format!("{}{NAME_SEP}{before}", g.name),
            false => g.name.clone(),
        });
    }
    Ok(out)
}

/// A UUID-shaped identifier derived from the grids, so that writing the
/// same grids gives the same file.
fn uuid(grids: &[VdbGrid]) -> String {
    let mut c = flate2::Crc::new();
    for g in grids {
        c.update(g.name.as_bytes());
        c.update(&(g.leaves.len() as u64).to_le_bytes());
        c.update(&g.active_value_sum().to_le_bytes());
    }
    let a = c.sum();
    c.update(b"fogbank");
    let b = c.sum();
    let hex = format!("{a:08x}{b:08x}{:016x}", (a as u64) << 32 | b as u64);
    format!(
        "{}-{}-4{}-8{}-{}",
        &hex[0..8],
        &hex[8..12],
        &hex[13..16],
        &hex[17..20],
        &hex[20..32]
    )
}

fn write_grid(out: &mut Vec<u8>, g: &VdbGrid, name: &str, options: VdbOptions) -> Result<()> {
    let tree = Tree::build(g)?;
    let map = transform(g)?;
    out.string(name);
    let suffix = if options.half { HALF_SUFFIX } else { "" };
    out.string(&format!("{FLOAT_TREE}{suffix}"));
    out.string(""); // no instance parent
    let offsets_at = out.len();
    out.extend_from_slice(&[0u8; 24]);
    let grid_pos = out.len();
    let mask = if options.active_mask {
        COMPRESS_ACTIVE_MASK
    } else {
        0
    };
    out.u32(
        mask | match options.codec {
            Codec::None => 0,
            Codec::Zip => COMPRESS_ZIP,
            Codec::Blosc => COMPRESS_BLOSC,
        },
    );
    // Metadata: the class, the name (OpenVDB takes a grid's name from its
    // metadata, not from the descriptor) and, for half grids, the flag
    // without which OpenVDB reads the node values as full floats.
    out.u32(2 + options.half as u32);
    for (key, value) in [("class", g.grid_class.name()), ("name", g.name.as_str())] {
        out.string(key);
        out.string("string");
        out.string(value);
    }
    if options.half {
        out.string("is_saved_as_half_float");
        out.string("bool");
        out.u32(1);
        out.u8(1);
    }
    out.extend_from_slice(&map);
    let mut leaves = Vec::new();
    write_topology(out, &tree, options, &mut leaves)?;
    let block_pos = out.len();
    for leaf in leaves {
        out.mask(&leaf.active);
        write_values(
            out,
            &leaf.values[..],
            &leaf.active,
            tree.background,
            options,
        )?;
    }
    let end_pos = out.len();
    for (k, v) in [grid_pos, block_pos, end_pos].into_iter().enumerate() {
        put_at(out, offsets_at + 8 * k, (v as i64).to_le_bytes());
    }
    Ok(())
}

/// The grid's transform map, type name first.
fn transform(g: &VdbGrid) -> Result<Vec<u8>> {
    let m = &g.index_to_world;
    let finite = m.iter().flatten().all(|v| v.is_finite());
    let l = glam::DMat3::from_cols_array_2d(&[
        [m[0][0], m[1][0], m[2][0]],
        [m[0][1], m[1][1], m[2][1]],
        [m[0][2], m[1][2], m[2][2]],
    ]);
    if !finite
        || m[3] != [0.0, 0.0, 0.0, 1.0]
        || l.determinant() == 0.0
        || !l.determinant().is_finite()
    {
        return Err(VolumeError::Invalid(format!(
            "grid `{}`: index-to-world map {m:?} is not an invertible affine map",
            g.name
        )));
    }
    let s = m[0][0];
    let uniform = (0..3).all(|r| (0..3).all(|c| m[r][c] == if r == c { s } else { 0.0 }));
    let mut out = Vec::new();
    if uniform {
        // translation, scale, voxel size, 1/scale, 1/scale², 1/(2·scale)
        out.string("UniformScaleTranslateMap");
        for v in [m[0][3], m[1][3], m[2][3]] {
            out.f64(v);
        }
        // The inverses as OpenVDB derives them from 1/scale.
        let inv = 1.0 / s;
        for v in [s, s, inv, inv * inv, inv / 2.0] {
            for _ in 0..3 {
                out.f64(v);
            }
        }
    } else {
        // OpenVDB's matrices act on row vectors: the transpose, with the
        // translation in the last row.
        out.string("AffineMap");
        // Column `r` of `m` is row `r` of OpenVDB's matrix: linear part and
        // translation, then the projective column (0, 0, 0, 1).
        for r in 0..4 {
            for row in m.iter().take(3) {
                out.f64(row[r]);
            }
            out.f64(if r == 3 { 1.0 } else { 0.0 });
        }
    }
    Ok(out)
}

/// The tree's topology; collects the leaves in the order their buffers
/// must follow.
fn write_topology<'g>(
    out: &mut Vec<u8>,
    tree: &Tree<'g>,
    options: VdbOptions,
    leaves: &mut Vec<&'g VdbLeaf>,
) -> Result<()> {
    out.i32(1); // buffer count
    out.f32(tree.background);
    let tiles: Vec<_> = tree
        .root
        .iter()
        .filter_map(|(o, e)| match e {
            RootEntry::Tile(t) => Some((*o, *t)),
            RootEntry::Child(_) => None,
        })
        .collect();
    let uppers: Vec<_> = tree.uppers().collect();
    out.u32(tiles.len() as u32);
    out.u32(uppers.len() as u32);
    for (o, t) in tiles {
        for v in o {
            out.i32(v);
        }
        out.f32(t.value);
        out.u8(t.active as u8);
    }
    for upper in uppers {
        for v in upper.origin {
            out.i32(v);
        }
        internal_head(out, upper, 5, tree.background, options)?;
        for lower in upper.children.values() {
            internal_head(out, lower, 4, tree.background, options)?;
            for leaf in lower.children.values() {
                out.mask(&leaf.active);
                leaves.push(leaf);
            }
        }
    }
    Ok(())
}

/// An internal node's masks and table of values (tile values; the
/// background in empty slots; zero where a child is, as OpenVDB writes).
fn internal_head<C>(
    out: &mut Vec<u8>,
    node: &Internal<C>,
    log2: u32,
    background: f32,
    options: VdbOptions,
) -> Result<()> {
    let n = 1usize << (3 * log2);
    let mut child_mask = vec![0u64; n / 64];
    let mut value_mask = vec![0u64; n / 64];
    let mut values = vec![background; n];
    for &i in node.children.keys() {
        child_mask[i as usize / 64] |= 1 << (i % 64);
        values[i as usize] = 0.0;
    }
    for (&i, &TileValue { value, active }) in &node.tiles {
        values[i as usize] = value;
        if active {
            value_mask[i as usize / 64] |= 1 << (i % 64);
        }
    }
    debug_assert!(node.children.keys().all(|&i| {
        let o = child_origin(node.origin, i, log2, if log2 == 5 { 7 } else { 3 });
        o.iter().zip(node.origin).all(|(a, b)| a >= &b)
    }));
    out.mask(&child_mask);
    out.mask(&value_mask);
    write_values(out, &values, &value_mask, background, options)
}

/// One node buffer: the per-node indicator, then the values, half or
/// full, through the codec. With active-mask compression, a node whose
/// inactive values all equal the background (or its negation) stores only
/// its active values (indicators 0 and 1), as OpenVDB does; any other node
/// stores all of them.
fn write_values(
    out: &mut Vec<u8>,
    values: &[f32],
    value_mask: &[u64],
    background: f32,
    options: VdbOptions,
) -> Result<()> {
    let active = |i: usize| value_mask[i / 64] >> (i % 64) & 1 == 1;
    let inactive_all =
        |v: f32| (0..values.len()).all(|i| active(i) || values[i].to_bits() == v.to_bits());
    let meta = if !options.active_mask {
        NO_MASK_AND_ALL_VALS
    } else if inactive_all(background) {
        NO_MASK_OR_INACTIVE_VALS
    } else if inactive_all(-background) {
        NO_MASK_AND_MINUS_BG
    } else {
        NO_MASK_AND_ALL_VALS
    };
    out.u8(meta);
    let kept: Vec<f32> = match meta {
        NO_MASK_AND_ALL_VALS => values.to_vec(),
        _ => (0..values.len())
            .filter(|&i| active(i))
            .map(|i| values[i])
            .collect(),
    };
    // OpenVDB writes nothing at all, not even a size, for an empty half
    // buffer.
    if options.half && kept.is_empty() {
        return Ok(());
    }
    write_chunk(out, &kept, options)
}

/// Values as half or full floats, raw or as a Zip or Blosc chunk.
fn write_chunk(out: &mut Vec<u8>, values: &[f32], options: VdbOptions) -> Result<()> {
    let (raw, typesize): (Vec<u8>, usize) = if options.half {
        let b = values
            .iter()
            .flat_map(|&v| half::f16::from_f32(v).to_bits().to_le_bytes())
            .collect();
        (b, 2)
    } else {
        (values.iter().flat_map(|v| v.to_le_bytes()).collect(), 4)
    };
    let packed = match options.codec {
        Codec::None => {
            out.extend_from_slice(&raw);
            return Ok(());
        }
        Codec::Zip => zlib(&raw),
        Codec::Blosc => blosc(&raw, typesize)
            .ok_or_else(|| VolumeError::Invalid("node buffer too large for Blosc".into()))?,
    };
    if packed.len() < raw.len() {
        out.i64(packed.len() as i64);
        out.extend_from_slice(&packed);
    } else {
        out.i64(-(raw.len() as i64));
        out.extend_from_slice(&raw);
    }
    Ok(())
}

//! `GridData` (672 B at the start of a grid buffer) and `TreeData` (64 B
//! after it): magic, checksum, version, size, class, type, the index→world
//! `Map`, and the offsets and counts of the tree's nodes.

use super::gridbuf::GridBuf;
use super::layout::{type_name, ValueKind};
use super::segment::{version_string, GRID_DATA_LEN, MAGIC_GRID, MAGIC_NUMB, MAJOR};
use crate::error::Result;

/// `GridData` offsets.
const CHECKSUM: usize = 8;
const VERSION: usize = 16;
const GRID_SIZE: usize = 32;
/// The `Map`'s double-precision matrix and translation (after its f32 copies).
const MAP_MAT_D: usize = 296 + 88;
const MAP_VEC_D: usize = MAP_MAT_D + 2 * 72;
const GRID_CLASS: usize = 632;
const GRID_TYPE: usize = 636;
/// `TreeData` follows `GridData`.
pub(super) const TREE: usize = GRID_DATA_LEN;
const TREE_LEN: usize = 64;
/// `GridData` and `TreeData`: what [`parse_head`] reads.
pub(super) const HEAD_LEN: usize = GRID_DATA_LEN + TREE_LEN;

/// What the tree reader needs from `GridData` and `TreeData`.
pub(super) struct GridHead {
    pub(super) checksum: u64,
    pub(super) version: u32,
    pub(super) kind: ValueKind,
    pub(super) grid_class: u32,
    /// Row-major, world = M · (i, j, k, 1).
    pub(super) index_to_world: [[f64; 4]; 4],
    /// Buffer offset of the first node of each level: leaf, lower, upper,
    /// root (NanoVDB stores them relative to `TreeData`).
    pub(super) node_offset: [usize; 4],
    /// Leaf, lower and upper node counts.
    pub(super) node_count: [u32; 3],
}

pub(super) fn parse_head(b: &GridBuf) -> Result<GridHead> {
    b.bytes(0, GRID_DATA_LEN + TREE_LEN, "grid and tree header")?;
    let magic = b.u64(0, "grid magic")?;
    if magic != MAGIC_NUMB && magic != MAGIC_GRID {
        return Err(b.fail(0, format!("bad grid magic {magic:#018x}")));
    }
    let version = b.u32(VERSION, "grid version")?;
    if version >> 21 != MAJOR {
        return Err(b.fail(
            VERSION,
            format!(
                "grid has NanoVDB version {}; only major version {MAJOR} can be read",
                version_string(version)
            ),
        ));
    }
    let size = b.u64(GRID_SIZE, "grid size")?;
    if size != b.len() as u64 {
        return Err(b.fail(
            GRID_SIZE,
            format!(
                "grid declares {size} bytes but its buffer holds {}",
                b.len()
            ),
        ));
    }
    let grid_type = b.u32(GRID_TYPE, "grid type")?;
    let kind = ValueKind::from_grid_type(grid_type).ok_or_else(|| {
        b.fail(
            GRID_TYPE,
            format!(
                "grid type {} ({grid_type}) cannot be read",
                type_name(grid_type)
            ),
        )
    })?;
    let mut node_offset = [0usize; 4];
    for (level, o) in node_offset.iter_mut().enumerate() {
        let at = TREE + 8 * level;
        let rel = b.u64(at, "tree node offset")?;
        *o = usize::try_from(rel)
            .ok()
            .and_then(|r| r.checked_add(TREE))
            .filter(|&o| o <= b.len())
            .ok_or_else(|| b.fail(at, format!("tree node offset {rel} lies outside the grid")))?;
    }
    let mut node_count = [0u32; 3];
    for (level, c) in node_count.iter_mut().enumerate() {
        *c = b.u32(TREE + 32 + 4 * level, "tree node count")?;
    }
    Ok(GridHead {
        checksum: b.u64(CHECKSUM, "grid checksum")?,
        version,
        kind,
        grid_class: b.u32(GRID_CLASS, "grid class")?,
        index_to_world: map(b)?,
        node_offset,
        node_count,
    })
}

/// The `Map`'s double-precision affine map: `world = matD · ijk + vecD`
/// with `matD` row-major.
fn map(b: &GridBuf) -> Result<[[f64; 4]; 4]> {
    let mut m = [[0.0; 4]; 4];
    for (r, row) in m.iter_mut().take(3).enumerate() {
        for (c, v) in row.iter_mut().take(3).enumerate() {
            *v = b.f64(MAP_MAT_D + 8 * (3 * r + c), "map matrix")?;
        }
        row[3] = b.f64(MAP_VEC_D + 8 * r, "map translation")?;
    }
    m[3][3] = 1.0;
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Err(b.fail(MAP_MAT_D, "index-to-world map has non-finite entries"));
    }
    Ok(m)
}

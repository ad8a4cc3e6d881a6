//! The tree, flattened into leaves and tiles as the OpenVDB reader does:
//! root tiles (keyed by origin, each a value or a child offset), the tiles
//! and children of the upper (32³) and lower (16³) internal nodes, and the
//! leaves. Children are reached through their parent's offsets, and their
//! origins follow from their place in the parent, as NanoVDB's accessors
//! find them. Root entries are visited in OpenVDB's order (by origin), and
//! each node's tiles before its children, so a grid converted from an
//! OpenVDB file flattens to the same lists as the OpenVDB file itself.

use std::collections::HashSet;

use super::gridbuf::GridBuf;
use super::griddata::GridHead;
use super::layout::{Layout, NodeLayout, FP_CODES};
use crate::error::Result;
use crate::loaders::vdb::Tile;

/// Where a leaf lies in the buffer, and its origin.
#[derive(Clone, Copy)]
pub(super) struct LeafAt {
    pub(super) at: usize,
    pub(super) origin: [i32; 3],
}

/// The flattened tree, and where each node lies (for the full checksum).
pub(super) struct Flat<const K: usize> {
    pub(super) background: [f32; K],
    pub(super) tiles: Vec<Tile<K>>,
    /// In the walk's order.
    pub(super) leaves: Vec<LeafAt>,
    /// Buffer offsets and sizes of the upper and lower nodes.
    pub(super) nodes: [Vec<(usize, usize)>; 2],
}

/// Tree walk state: the buffer, the layout, and the nodes reached so far,
/// which bound the work by the node counts `TreeData` declares.
struct Walk<'b, 'a, const K: usize> {
    b: &'b GridBuf<'a>,
    lay: Layout,
    counts: [u32; 3],
    seen: HashSet<usize>,
    flat: Flat<K>,
}

/// Root offsets: bbox (6 × i32), table size (u32).
const ROOT_TABLE_SIZE: usize = 24;

pub(super) fn read_tree<const K: usize>(b: &GridBuf, head: &GridHead) -> Result<Flat<K>> {
    let lay = Layout::new(head.kind);
    let root = head.node_offset[3];
    b.bytes(root, lay.root_size, "root node")?;
    let table = b.u32(root + ROOT_TABLE_SIZE, "root table size")? as usize;
    let tiles_at = root + lay.root_size;
    if table > (b.len() - tiles_at) / lay.tile_size {
        return Err(b.fail(
            root + ROOT_TABLE_SIZE,
            format!("root table of {table} tiles does not fit in the grid buffer"),
        ));
    }
    // Node counts can only be as large as the buffer holds nodes (the
    // smallest FpN leaf has 1-bit codes).
    let sizes = [
        lay.upper.size,
        lay.lower.size,
        lay.leaf_size.max(FP_CODES + 64),
    ];
    let counts = [head.node_count[2], head.node_count[1], head.node_count[0]];
    for (c, s) in counts.iter().zip(sizes) {
        if *c as usize > b.len() / s {
            return Err(b.fail(super::griddata::TREE, format!("implausible node count {c}")));
        }
    }
    let elem = lay.kind.element_size();
    let mut w = Walk::<K> {
        b,
        lay,
        counts,
        seen: HashSet::new(),
        flat: Flat {
            background: value::<K>(b, root + lay.root_background, elem, "background")?,
            tiles: Vec::new(),
            leaves: Vec::new(),
            nodes: [Vec::new(), Vec::new()],
        },
    };
    let mut entries = Vec::with_capacity(table);
    for n in 0..table {
        let at = tiles_at + n * lay.tile_size;
        let key = b.u64(at, "root tile key")?;
        entries.push((key_origin(key), at));
    }
    entries.sort_by_key(|&(origin, _)| origin);
    let mut children = Vec::new();
    for &(origin, at) in &entries {
        let child = b.i64(at + 8, "root tile child")?;
        if child != 0 {
            children.push((origin, child));
            continue;
        }
        let v = value::<K>(b, at + lay.tile_value, elem, "root tile value")?;
        let active = b.u32(at + 16, "root tile state")? != 0;
        w.tile(origin, 4096, v, active);
    }
    for (origin, child) in children {
        let at = b.child(root, child, lay.upper.size, "root child")?;
        w.internal(at, origin, lay.upper)?;
    }
    Ok(w.flat)
}

/// A root key packs the upper node origin's top 20 bits of x, y and z in
/// 21-bit fields (x highest).
fn key_origin(key: u64) -> [i32; 3] {
    let field = |shift: u32| ((((key >> shift) & ((1 << 21) - 1)) << 12) as u32) as i32;
    [field(42), field(21), field(0)]
}

/// `K` floats at `at`, each an f32 or (8-byte elements) an f64.
fn value<const K: usize>(b: &GridBuf, at: usize, elem: usize, what: &str) -> Result<[f32; K]> {
    let mut v = [0.0f32; K];
    for (c, x) in v.iter_mut().enumerate() {
        *x = if elem == 8 {
            b.f64(at + 8 * c, what)? as f32
        } else {
            b.f32(at + 4 * c, what)?
        };
    }
    Ok(v)
}

fn bit_on(mask: &[u64], n: usize) -> bool {
    mask[n / 64] >> (n % 64) & 1 == 1
}

impl<const K: usize> Walk<'_, '_, K> {
    /// Keeps a tile that is active or differs from the background (as
    /// the OpenVDB reader does: level-set interiors are inactive tiles).
    fn tile(&mut self, origin: [i32; 3], size: u32, value: [f32; K], active: bool) {
        if active || value != self.flat.background {
            self.flat.tiles.push(Tile {
                origin,
                size,
                value,
                active,
            });
        }
    }

    /// Marks the node at `at` of `level` (0 upper, 1 lower, 2 leaf) as
    /// reached: once only, and no more nodes than the tree declares.
    fn reach(&mut self, at: usize, size: usize, level: usize, what: &str) -> Result<()> {
        if !self.seen.insert(at) {
            return Err(self.b.fail(at, format!("{what} is reached twice")));
        }
        let reached = match level {
            2 => self.flat.leaves.len(),
            _ => self.flat.nodes[level].len(),
        };
        if reached >= self.counts[level] as usize {
            return Err(self.b.fail(
                at,
                format!(
                    "more {what}s than the {} the tree declares",
                    self.counts[level]
                ),
            ));
        }
        if level < 2 {
            self.flat.nodes[level].push((at, size));
        }
        Ok(())
    }

    /// An internal node at `at` with origin `origin`: its tiles, then its
    /// children in table order.
    fn internal(&mut self, at: usize, origin: [i32; 3], node: NodeLayout) -> Result<()> {
        let upper = node.log2 == 5;
        let what = if upper {
            "upper internal node"
        } else {
            "lower internal node"
        };
        self.reach(at, node.size, if upper { 0 } else { 1 }, what)?;
        let b = self.b;
        let n = 1usize << (3 * node.log2);
        let values = b.mask(at + node.value_mask, n / 64, "internal node value mask")?;
        let children = b.mask(at + node.child_mask, n / 64, "internal node child mask")?;
        let dim = (1usize << node.log2) - 1;
        let child_origin = |i: usize| {
            let xyz = [i >> (2 * node.log2), (i >> node.log2) & dim, i & dim];
            std::array::from_fn(|c| origin[c].wrapping_add((xyz[c] as i32) << node.child_total))
        };
        let elem = self.lay.kind.element_size();
        for i in (0..n).filter(|&i| !bit_on(&children, i)) {
            let v = value::<K>(b, at + node.table + i * node.entry, elem, "tile value")?;
            self.tile(
                child_origin(i),
                1 << node.child_total,
                v,
                bit_on(&values, i),
            );
        }
        for i in (0..n).filter(|&i| bit_on(&children, i)) {
            let offset = b.i64(at + node.table + i * node.entry, "child offset")?;
            if upper {
                let child = b.child(at, offset, self.lay.lower.size, "lower node")?;
                self.internal(child, child_origin(i), self.lay.lower)?;
            } else {
                let child = b.child(at, offset, FP_CODES, "leaf")?;
                self.leaf(child, child_origin(i))?;
            }
        }
        Ok(())
    }

    fn leaf(&mut self, at: usize, origin: [i32; 3]) -> Result<()> {
        self.reach(at, 0, 2, "leaf")?;
        self.flat.leaves.push(LeafAt { at, origin });
        Ok(())
    }
}

//! One NanoVDB grid buffer (NanoVDB 32.4, `NanoVDB.h`): `GridData` (672
//! B), `TreeData` (64 B), the root and its tile table, then every upper
//! (32³) node, every lower (16³) node and every leaf, each level in
//! breadth-first order (the order `nanovdb_convert` writes; the grid flags
//! say so). Children are reached through signed byte offsets from their
//! parent; node sizes and field offsets come from the reader's
//! [`Layout`], so that both follow one description of the format.
//!
//! Every node carries the index box and statistics of its active values
//! ([`Stats`]); quantised leaves (Fp8, Fp16) store each value as
//! `code · quantum + minimum` with the minimum and the quantum taken over
//! all 512 values and codes rounded to nearest, as NanoVDB's converter
//! does without dithering. The checksum is NanoVDB 32.4's partial one: the
//! CRC32 of the head (from byte 16 to the end of the root's tile table) in
//! the low half, the nodes' half marked "not computed".

use super::bytes::put_at;
use super::nanovdb_map::Map;
use super::nanovdb_quantise::Quantised;
use super::nanovdb_stats::Stats;
use super::options::NanoValue;
use super::tree::{child_origin, Internal, RootEntry, Tree, LOWER_TOTAL, UPPER_TOTAL};
use crate::loaders::nanovdb::layout::{
    Layout, NodeLayout, ValueKind, FP_CODES, FP_MINIMUM, FP_QUANTUM, LEAF_MASK,
};
use crate::loaders::vdb::{GridClass, VdbGrid, VdbLeaf};
use crate::{Result, VolumeError};

/// NanoVDB 32.4.2, packed `major << 21 | minor << 10 | patch`.
pub(crate) const VERSION: u32 = (32 << 21) | (4 << 10) | 2;
/// "NanoVDB0".
pub(crate) const MAGIC: u64 = 0x3042_4456_6f6e_614e;
const GRID_DATA_LEN: usize = 672;
const TREE_DATA_LEN: usize = 64;
const ROOT: usize = GRID_DATA_LEN + TREE_DATA_LEN;
/// `GridData` flags: index box, min/max, average, standard deviation,
/// breadth-first node order.
const FLAGS_WITH_STATS: u32 = 2 | 4 | 8 | 16 | 32;
const FLAG_BREADTH_FIRST: u32 = 32;
/// Node flag: the node's box is set.
const NODE_HAS_BBOX: u8 = 2;
/// Longest name `GridData` holds (256 bytes with the terminating NUL).
const MAX_NAME: usize = 255;

/// What the file's segment metadata repeats about the grid.
pub(crate) struct GridBuffer {
    pub(crate) bytes: Vec<u8>,
    pub(crate) grid_type: u32,
    pub(crate) grid_class: u32,
    pub(crate) world_bbox: [f64; 6],
    pub(crate) index_bbox: [i32; 6],
    pub(crate) voxel_size: [f64; 3],
    /// Leaf, lower and upper nodes.
    pub(crate) node_count: [u32; 3],
    /// Active tiles in lower nodes, upper nodes and the root.
    pub(crate) tile_count: [u32; 3],
    pub(crate) voxel_count: u64,
}

fn kind_of(v: NanoValue) -> (ValueKind, u32) {
    match v {
        NanoValue::Float => (ValueKind::Float, 1),
        NanoValue::Fp8 => (ValueKind::Fp8, 14),
        NanoValue::Fp16 => (ValueKind::Fp16, 15),
    }
}

fn class_code(c: GridClass) -> u32 {
    match c {
        GridClass::Unknown => 0,
        GridClass::LevelSet => 1,
        GridClass::FogVolume => 2,
        GridClass::Staggered => 3,
    }
}

/// The tree's nodes in breadth-first order with their statistics.
struct Nodes<'t, 'g> {
    uppers: Vec<&'t Internal<Internal<&'g VdbLeaf>>>,
    lowers: Vec<&'t Internal<&'g VdbLeaf>>,
    leaves: Vec<&'g VdbLeaf>,
    /// Per node, and for the whole tree.
    upper_stats: Vec<Stats>,
    lower_stats: Vec<Stats>,
    leaf_stats: Vec<Stats>,
    root_stats: Stats,
    /// Per leaf, for quantised grids.
    quantised: Vec<Quantised>,
    tile_count: [u32; 3],
}

/// Builds the grid buffer of `g` with values of type `value`.
pub(crate) fn build(g: &VdbGrid, value: NanoValue) -> Result<GridBuffer> {
    if g.name.len() > MAX_NAME || g.name.contains('\0') {
        return Err(VolumeError::Invalid(format!(
            "grid name {:?}: NanoVDB names are at most {MAX_NAME} bytes without NUL",
            g.name
        )));
    }
    let (kind, grid_type) = kind_of(value);
    let lay = Layout::new(kind);
    let tree = Tree::build(g)?;
    let nodes = collect(&tree, kind.code_bits());
    let map = Map::new(g)?;
    let entries = tree.root.len();
    let uppers_at = ROOT + lay.root_size + entries * lay.tile_size;
    let lowers_at = uppers_at + nodes.uppers.len() * lay.upper.size;
    let leaves_at = lowers_at + nodes.lowers.len() * lay.lower.size;
    let size = leaves_at + nodes.leaves.len() * lay.leaf_size;
    let mut buf = vec![0u8; size];
    write_root(&mut buf, &tree, &nodes, &lay, uppers_at);
    write_nodes(
        &mut buf,
        &nodes,
        &lay,
        [uppers_at, lowers_at, leaves_at],
        g.background,
    );
    let counts = [nodes.leaves.len(), nodes.lowers.len(), nodes.uppers.len()].map(|c| c as u32);
    let firsts = [leaves_at, lowers_at, uppers_at, ROOT];
    write_tree_data(
        &mut buf,
        firsts,
        counts,
        nodes.tile_count,
        nodes.root_stats.count,
    );
    let rs = &nodes.root_stats;
    let index_bbox = match rs.is_empty() {
        true => [0; 6],
        false => [rs.lo[0], rs.lo[1], rs.lo[2], rs.hi[0], rs.hi[1], rs.hi[2]],
    };
    let out = GridBuffer {
        world_bbox: map.world_bbox(rs),
        voxel_size: map.voxel_size(),
        bytes: Vec::new(),
        grid_type,
        grid_class: class_code(g.grid_class),
        index_bbox,
        node_count: counts,
        tile_count: nodes.tile_count,
        voxel_count: rs.count,
    };
    write_grid_data(&mut buf, g, &out, &map, rs.is_empty());
    let head_end = ROOT + lay.root_size + entries * lay.tile_size;
    let crc = crc32(&buf[16..head_end]);
    put_at(
        &mut buf,
        8,
        ((u32::MAX as u64) << 32 | crc as u64).to_le_bytes(),
    );
    Ok(GridBuffer { bytes: buf, ..out })
}

/// The upper nodes, lower nodes and leaves, each level from its first
/// byte in `at`, every child offset pointing into the next level.
fn write_nodes(buf: &mut [u8], nodes: &Nodes, lay: &Layout, at: [usize; 3], background: f32) {
    let [uppers_at, lowers_at, leaves_at] = at;
    let mut lower_index = 0;
    for (i, (u, s)) in nodes.uppers.iter().zip(&nodes.upper_stats).enumerate() {
        let at = uppers_at + i * lay.upper.size;
        let first = lowers_at + lower_index * lay.lower.size;
        let offsets =
            (0..u.children.len()).map(|k| (first + k * lay.lower.size) as i64 - at as i64);
        write_internal(buf, at, u, s, lay.upper, background, offsets.collect());
        lower_index += u.children.len();
    }
    let mut leaf_index = 0;
    for (i, (l, s)) in nodes.lowers.iter().zip(&nodes.lower_stats).enumerate() {
        let at = lowers_at + i * lay.lower.size;
        let first = leaves_at + leaf_index * lay.leaf_size;
        let offsets = (0..l.children.len()).map(|k| (first + k * lay.leaf_size) as i64 - at as i64);
        write_internal(buf, at, l, s, lay.lower, background, offsets.collect());
        leaf_index += l.children.len();
    }
    for (i, (leaf, s)) in nodes.leaves.iter().zip(&nodes.leaf_stats).enumerate() {
        let q = nodes.quantised.get(i);
        write_leaf(buf, leaves_at + i * lay.leaf_size, leaf, s, lay, q);
    }
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = flate2::Crc::new();
    c.update(bytes);
    c.sum()
}

/// Nodes in breadth-first order, and statistics from the leaves up.
/// Quantised grids' statistics are those of the values they store, as
/// NanoVDB computes them after quantising.
fn collect<'t, 'g>(tree: &'t Tree<'g>, bits: Option<u32>) -> Nodes<'t, 'g> {
    let uppers: Vec<_> = tree.uppers().collect();
    let lowers: Vec<_> = uppers.iter().flat_map(|u| u.children.values()).collect();
    let leaves: Vec<&'g VdbLeaf> = lowers
        .iter()
        .flat_map(|l| l.children.values().copied())
        .collect();
    let quantised: Vec<Quantised> = match bits {
        Some(bits) => leaves
            .iter()
            .map(|l| Quantised::new(&l.values, bits))
            .collect(),
        None => Vec::new(),
    };
    let leaf_stats: Vec<Stats> = match bits {
        Some(_) => (leaves.iter().zip(&quantised))
            .map(|(l, q)| leaf_stats(l, &q.decoded()))
            .collect(),
        None => leaves
            .iter()
            .map(|l| leaf_stats(l, &l.values[..]))
            .collect(),
    };
    let mut tile_count = [0u32; 3];
    let mut next = leaf_stats.iter();
    let lower_stats: Vec<Stats> = lowers
        .iter()
        .map(|l| {
            node_stats(
                l,
                4,
                LOWER_TOTAL,
                next.by_ref().take(l.children.len()),
                &mut tile_count[0],
            )
        })
        .collect();
    let mut next = lower_stats.iter();
    let upper_stats: Vec<Stats> = uppers
        .iter()
        .map(|u| {
            node_stats(
                u,
                5,
                UPPER_TOTAL,
                next.by_ref().take(u.children.len()),
                &mut tile_count[1],
            )
        })
        .collect();
    let mut root_stats = Stats::default();
    for s in &upper_stats {
        root_stats.merge(s);
    }
    for (o, e) in &tree.root {
        if let RootEntry::Tile(t) = e {
            if t.active {
                tile_count[2] += 1;
                root_stats.tile(t.value, 1 << 36, *o, o.map(|v| v.saturating_add(4095)));
            }
        }
    }
    Nodes {
        uppers,
        lowers,
        leaves,
        upper_stats,
        lower_stats,
        leaf_stats,
        root_stats,
        quantised,
        tile_count,
    }
}

/// Statistics of the active ones of `values`, the leaf's values as stored.
fn leaf_stats(leaf: &VdbLeaf, values: &[f32]) -> Stats {
    let mut s = Stats::default();
    for (i, &v) in values.iter().enumerate() {
        if leaf.active[i / 64] >> (i % 64) & 1 == 1 {
            let i = i as i32;
            let o = leaf.origin;
            s.voxel(v, [o[0] + (i >> 6), o[1] + ((i >> 3) & 7), o[2] + (i & 7)]);
        }
    }
    s
}

/// A node's statistics: its children's (in table order) and its active
/// tiles'; counts the active tiles into `tiles`.
fn node_stats<'s, C>(
    node: &Internal<C>,
    log2: u32,
    total: u32,
    children: impl Iterator<Item = &'s Stats>,
    tiles: &mut u32,
) -> Stats {
    let mut s = Stats::default();
    for c in children {
        s.merge(c);
    }
    let child_total = total - log2;
    let edge = (1i32 << child_total) - 1;
    for (&i, t) in node.tiles.iter().filter(|(_, t)| t.active) {
        *tiles += 1;
        let o = child_origin(node.origin, i, log2, child_total);
        s.tile(t.value, 1 << (3 * child_total), o, o.map(|v| v + edge));
    }
    s
}

/// Root: index box, table size, background and statistics, then one tile
/// per root entry: key, child offset (from the root), state, value.
fn write_root(buf: &mut [u8], tree: &Tree, nodes: &Nodes, lay: &Layout, uppers_at: usize) {
    write_bbox(buf, ROOT, &nodes.root_stats);
    put_at(buf, ROOT + 24, (tree.root.len() as u32).to_le_bytes());
    write_values(
        buf,
        ROOT + lay.root_background,
        tree.background,
        &nodes.root_stats,
    );
    let mut upper = 0;
    for (n, (o, e)) in tree.root.iter().enumerate() {
        let at = ROOT + lay.root_size + n * lay.tile_size;
        let key = o.map(|v| (v as u32 >> 12) as u64);
        put_at(
            buf,
            at,
            (key[0] << 42 | key[1] << 21 | key[2]).to_le_bytes(),
        );
        match e {
            RootEntry::Child(_) => {
                let child = uppers_at + upper * lay.upper.size;
                put_at(buf, at + 8, ((child - ROOT) as i64).to_le_bytes());
                upper += 1;
            }
            RootEntry::Tile(t) => {
                put_at(buf, at + 16, (t.active as u32).to_le_bytes());
                put_at(buf, at + lay.tile_value, t.value.to_le_bytes());
            }
        }
    }
}

/// The root's background, minimum, maximum, average and standard
/// deviation (all `f32` for the value types written), from `at`.
fn write_values(buf: &mut [u8], at: usize, background: f32, s: &Stats) {
    let [min, max, avg, std] = s.stored();
    for (k, v) in [background, min, max, avg, std].iter().enumerate() {
        put_at(buf, at + 4 * k, v.to_le_bytes());
    }
}

fn write_bbox(buf: &mut [u8], at: usize, s: &Stats) {
    if s.is_empty() {
        return;
    }
    for (k, v) in s.lo.iter().chain(&s.hi).enumerate() {
        put_at(buf, at + 4 * k, v.to_le_bytes());
    }
}

/// An internal node: box, flags, value and child masks, statistics, then
/// its table (tile values; the background in empty slots; child offsets
/// from this node, `offsets` in table order).
fn write_internal<C>(
    buf: &mut [u8],
    at: usize,
    node: &Internal<C>,
    s: &Stats,
    nl: NodeLayout,
    background: f32,
    offsets: Vec<i64>,
) {
    write_bbox(buf, at, s);
    if !s.is_empty() {
        put_at(buf, at + 24, (NODE_HAS_BBOX as u64).to_le_bytes());
    }
    let n = 1usize << (3 * nl.log2);
    let mut value_mask = vec![0u64; n / 64];
    let mut child_mask = vec![0u64; n / 64];
    for i in 0..n {
        put_at(buf, at + nl.table + i * nl.entry, background.to_le_bytes());
    }
    for (&i, t) in &node.tiles {
        put_at(
            buf,
            at + nl.table + i as usize * nl.entry,
            t.value.to_le_bytes(),
        );
        if t.active {
            value_mask[i as usize / 64] |= 1 << (i % 64);
        }
    }
    for (&i, off) in node.children.keys().zip(offsets) {
        put_at(
            buf,
            at + nl.table + i as usize * nl.entry,
            off.to_le_bytes(),
        );
        child_mask[i as usize / 64] |= 1 << (i % 64);
    }
    for (k, (v, c)) in value_mask.iter().zip(&child_mask).enumerate() {
        put_at(buf, at + nl.value_mask + 8 * k, v.to_le_bytes());
        put_at(buf, at + nl.child_mask + 8 * k, c.to_le_bytes());
    }
    let stats_at = nl.child_mask + n / 8;
    let [min, max, avg, std] = s.stored();
    for (k, v) in [min, max, avg, std].iter().enumerate() {
        put_at(buf, at + stats_at + 4 * k, v.to_le_bytes());
    }
}

/// A leaf: box (minimum, extent as bytes), flags, value mask, then its
/// statistics and values (full precision), or its minimum, quantum,
/// quantised statistics and codes.
fn write_leaf(
    buf: &mut [u8],
    at: usize,
    leaf: &VdbLeaf,
    s: &Stats,
    lay: &Layout,
    quantised: Option<&Quantised>,
) {
    let (lo, dif, flags) = match s.is_empty() {
        true => (leaf.origin, [0u8; 3], 0),
        false => (
            s.lo,
            std::array::from_fn(|k| (s.hi[k] - s.lo[k]) as u8),
            NODE_HAS_BBOX,
        ),
    };
    for (k, v) in lo.iter().enumerate() {
        put_at(buf, at + 4 * k, v.to_le_bytes());
    }
    buf[at + 12..at + 15].copy_from_slice(&dif);
    buf[at + 15] = flags;
    for (k, w) in leaf.active.iter().enumerate() {
        put_at(buf, at + LEAF_MASK + 8 * k, w.to_le_bytes());
    }
    let stored = s.stored();
    let Some(bits) = lay.kind.code_bits() else {
        for (k, v) in stored.iter().enumerate() {
            put_at(buf, at + 80 + 4 * k, v.to_le_bytes());
        }
        for (k, v) in leaf.values.iter().enumerate() {
            put_at(buf, at + lay.leaf_values + 4 * k, v.to_le_bytes());
        }
        return;
    };
    let q = quantised.expect("quantised leaves come with their codes");
    put_at(buf, at + FP_MINIMUM, q.minimum.to_le_bytes());
    put_at(buf, at + FP_QUANTUM, q.quantum.to_le_bytes());
    for (k, v) in q.stats_codes(s).iter().enumerate() {
        put_at(buf, at + 88 + 2 * k, v.to_le_bytes());
    }
    for (k, &code) in q.codes.iter().enumerate() {
        if bits == 16 {
            put_at(buf, at + FP_CODES + 2 * k, code.to_le_bytes());
        } else {
            buf[at + FP_CODES + k] = code as u8;
        }
    }
}

fn write_tree_data(
    buf: &mut [u8],
    firsts: [usize; 4],
    counts: [u32; 3],
    tiles: [u32; 3],
    voxels: u64,
) {
    let t = GRID_DATA_LEN;
    for (k, f) in firsts.iter().enumerate() {
        put_at(buf, t + 8 * k, ((f - t) as u64).to_le_bytes());
    }
    for (k, c) in counts.iter().chain(&tiles).enumerate() {
        put_at(buf, t + 32 + 4 * k, c.to_le_bytes());
    }
    put_at(buf, t + 56, voxels.to_le_bytes());
}

/// `GridData`: magic, version, flags, index and count, size, name, map,
/// world box, voxel size, class and type (the checksum comes last).
fn write_grid_data(buf: &mut [u8], g: &VdbGrid, out: &GridBuffer, map: &Map, empty: bool) {
    let size = buf.len() as u64;
    put_at(buf, 0, MAGIC.to_le_bytes());
    put_at(buf, 16, VERSION.to_le_bytes());
    let flags = if empty {
        FLAG_BREADTH_FIRST
    } else {
        FLAGS_WITH_STATS
    };
    put_at(buf, 20, flags.to_le_bytes());
    put_at(buf, 28, 1u32.to_le_bytes()); // grid 0 of 1
    put_at(buf, 32, size.to_le_bytes());
    buf[40..40 + g.name.len()].copy_from_slice(g.name.as_bytes());
    let flat = |m: &[[f64; 3]; 3]| -> Vec<f64> { m.iter().flatten().copied().collect() };
    let mut f32s = flat(&map.mat);
    f32s.extend(flat(&map.inv));
    f32s.extend(map.vec);
    f32s.push(1.0); // taper
    for (k, v) in f32s.iter().enumerate() {
        put_at(buf, 296 + 4 * k, (*v as f32).to_le_bytes());
        put_at(buf, 296 + 88 + 8 * k, v.to_le_bytes());
    }
    for (k, v) in out.world_bbox.iter().chain(&out.voxel_size).enumerate() {
        put_at(buf, 560 + 8 * k, v.to_le_bytes());
    }
    put_at(buf, 632, out.grid_class.to_le_bytes());
    put_at(buf, 636, out.grid_type.to_le_bytes());
}

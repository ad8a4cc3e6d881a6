//! The grid types the reader returns: descriptors, leaves, tiles and the
//! flattened float grid with its summaries; and the parsed file header and
//! grid descriptors that the header parser and the tree reader share.

use super::format::{FLOAT_TREE, VEC3S_TREE};

/// How OpenVDB classifies a grid; renderers treat fog volumes as density and
/// level sets as signed distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridClass {
    FogVolume,
    LevelSet,
    Staggered,
    Unknown,
}

impl GridClass {
    /// The `class` metadata value OpenVDB writes for it.
    pub fn name(self) -> &'static str {
        match self {
            GridClass::FogVolume => "fog volume",
            GridClass::LevelSet => "level set",
            GridClass::Staggered => "staggered",
            GridClass::Unknown => "unknown",
        }
    }

    pub(super) fn from_meta(s: &str) -> GridClass {
        match s {
            "fog volume" => GridClass::FogVolume,
            "level set" => GridClass::LevelSet,
            "staggered" => GridClass::Staggered,
            _ => GridClass::Unknown,
        }
    }
}

/// What `list_grids` reports per grid, enough to pick one without reading it.
#[derive(Debug, Clone, PartialEq)]
pub struct VdbGridDescriptor {
    /// The grid name; duplicated names carry an index, `name[N]`, which
    /// [`read_grid`](super::read_grid) accepts.
    pub name: String,
    /// Value type from the tree type string, e.g. `float`, `vec3s`, `int32`.
    pub value_type: String,
    pub grid_class: GridClass,
    pub stored_as_half: bool,
    /// True for float scalar grids with the standard tree layout, which
    /// [`read_grid`](super::read_grid) reads. (`vec3s` grids are read by
    /// [`read_vec3_grid`](super::read_vec3_grid) instead.)
    pub supported: bool,
}

/// The parsed file header: format version and every grid's descriptor.
pub(super) struct FileHeader {
    pub(super) version: u32,
    pub(super) descs: Vec<GridDesc>,
}

/// One grid descriptor as the file header stores it.
pub(super) struct GridDesc {
    /// As stored, possibly with a `\x1e N` suffix.
    pub(super) unique_name: String,
    /// Without the suffix.
    pub(super) name: String,
    /// `name[N]` when there was a suffix; what users see and may pass back.
    pub(super) display_name: String,
    /// Tree type without the `_HalfFloat` suffix, e.g. `Tree_float_5_4_3`.
    pub(super) type_name: String,
    pub(super) value_type: String,
    pub(super) half: bool,
    pub(super) supported: bool,
    pub(super) instance_parent: String,
    pub(super) grid_pos: usize,
    pub(super) end_pos: usize,
}

impl GridDesc {
    /// Floats per value for the trees the reader can read: 1 for `float`,
    /// 3 for `vec3s` grids.
    pub(super) fn components(&self) -> Option<usize> {
        match self.type_name.as_str() {
            FLOAT_TREE => Some(1),
            VEC3S_TREE => Some(3),
            _ => None,
        }
    }
}

/// An 8³ leaf node. `values` and `active` use OpenVDB's layout: voxel
/// `(x, y, z)` relative to `origin` sits at index `x * 64 + y * 8 + z`.
#[derive(Debug, Clone, PartialEq)]
pub struct VdbLeaf {
    pub origin: [i32; 3],
    pub values: Box<[f32; 512]>,
    pub active: [u64; 8],
}

/// A constant region: an internal-node or root tile. Inactive tiles are kept
/// only when their value differs from the background (level-set interiors).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VdbTile {
    pub origin: [i32; 3],
    /// Edge length in voxels: 8 (16³ node tile), 128 (32³ node tile) or 4096 (root tile).
    pub size: u32,
    pub value: f32,
    pub active: bool,
}

/// A tile of `K` floats per voxel as a tree stores it (OpenVDB's and
/// NanoVDB's readers), before it is split into one grid per component.
pub(crate) struct Tile<const K: usize> {
    pub(crate) origin: [i32; 3],
    pub(crate) size: u32,
    pub(crate) value: [f32; K],
    pub(crate) active: bool,
}

impl<const K: usize> Tile<K> {
    /// Component `c` of the tile.
    pub(crate) fn component(&self, c: usize) -> VdbTile {
        VdbTile {
            origin: self.origin,
            size: self.size,
            value: self.value[c],
            active: self.active,
        }
    }
}

/// One float grid, flattened into leaves and tiles. A `vec3s` grid is read
/// as three of these, one per component, named `name.x`, `name.y` and
/// `name.z`, with identical leaves, tiles, masks, transform and class.
#[derive(Debug, Clone, PartialEq)]
pub struct VdbGrid {
    pub name: String,
    pub grid_class: GridClass,
    /// The OpenVDB file format version; for a grid read from a NanoVDB
    /// file, its packed NanoVDB version (see
    /// [`nanovdb::version_string`](crate::loaders::nanovdb::version_string)).
    pub file_version: u32,
    pub stored_as_half: bool,
    /// `none`, or `zip`/`blosc`/`active-mask` joined with ` + `; for a
    /// NanoVDB grid its codec (`none`, `zip`, `blosc`), after the
    /// quantisation (`Fp4 + zip`) for quantised grids.
    pub compression: String,
    pub background: f32,
    /// Row-major affine map, world = M · (i, j, k, 1).
    pub index_to_world: [[f64; 4]; 4],
    pub leaves: Vec<VdbLeaf>,
    pub tiles: Vec<VdbTile>,
}

impl VdbGrid {
    /// Active voxels in leaves plus the volume of active tiles.
    pub fn active_voxel_count(&self) -> u64 {
        let leaves: u64 = self
            .leaves
            .iter()
            .map(|l| l.active.iter().map(|w| w.count_ones() as u64).sum::<u64>())
            .sum();
        let tiles: u64 = self
            .tiles
            .iter()
            .filter(|t| t.active)
            .map(|t| (t.size as u64).pow(3))
            .sum();
        leaves + tiles
    }

    /// Inclusive index-space box of the active voxels, as `vdb_print` shows it.
    pub fn active_bbox(&self) -> Option<([i32; 3], [i32; 3])> {
        let mut lo = [i32::MAX; 3];
        let mut hi = [i32::MIN; 3];
        let mut any = false;
        let mut grow = |a: [i32; 3], b: [i32; 3]| {
            any = true;
            for c in 0..3 {
                lo[c] = lo[c].min(a[c]);
                hi[c] = hi[c].max(b[c]);
            }
        };
        for leaf in &self.leaves {
            for_each_active(&leaf.active, |idx| {
                let p = leaf_coord(leaf.origin, idx);
                grow(p, p);
            });
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            let e = t.size as i32 - 1;
            let b = [0, 1, 2].map(|c| t.origin[c].saturating_add(e));
            grow(t.origin, b);
        }
        any.then_some((lo, hi))
    }

    /// Smallest and largest active value (leaf voxels and active tiles).
    pub fn active_value_range(&self) -> Option<(f32, f32)> {
        let mut range: Option<(f32, f32)> = None;
        let mut add = |v: f32| {
            range = Some(match range {
                None => (v, v),
                Some((a, b)) => (a.min(v), b.max(v)),
            })
        };
        for leaf in &self.leaves {
            for_each_active(&leaf.active, |idx| add(leaf.values[idx]));
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            add(t.value);
        }
        range
    }

    /// Sum of active values, each tile counted once per voxel it covers.
    pub fn active_value_sum(&self) -> f64 {
        let mut sum = 0.0f64;
        for leaf in &self.leaves {
            for_each_active(&leaf.active, |idx| sum += leaf.values[idx] as f64);
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            sum += t.value as f64 * (t.size as f64).powi(3);
        }
        sum
    }

    /// The value stored at `ijk`: the leaf voxel, else the innermost tile,
    /// else the background. A linear search, meant for tests and tools.
    pub fn value_at(&self, ijk: [i32; 3]) -> f32 {
        let leaf_origin = ijk.map(|v| v & !7);
        if let Some(leaf) = self.leaves.iter().find(|l| l.origin == leaf_origin) {
            let idx = (((ijk[0] & 7) << 6) | ((ijk[1] & 7) << 3) | (ijk[2] & 7)) as usize;
            return leaf.values[idx];
        }
        let inside = |t: &&VdbTile| {
            (0..3).all(|c| {
                let d = ijk[c] as i64 - t.origin[c] as i64;
                d >= 0 && d < t.size as i64
            })
        };
        match self.tiles.iter().filter(inside).min_by_key(|t| t.size) {
            Some(t) => t.value,
            None => self.background,
        }
    }
}

fn leaf_coord(origin: [i32; 3], idx: usize) -> [i32; 3] {
    let i = idx as i32;
    [
        origin[0].wrapping_add(i >> 6),
        origin[1].wrapping_add((i >> 3) & 7),
        origin[2].wrapping_add(i & 7),
    ]
}

pub(super) fn for_each_active(mask: &[u64], mut f: impl FnMut(usize)) {
    for (w, &word) in mask.iter().enumerate() {
        let mut bits = word;
        while bits != 0 {
            let b = bits.trailing_zeros() as usize;
            f(w * 64 + b);
            bits &= bits - 1;
        }
    }
}

pub(super) fn bit_on(mask: &[u64], idx: usize) -> bool {
    mask[idx / 64] >> (idx % 64) & 1 == 1
}

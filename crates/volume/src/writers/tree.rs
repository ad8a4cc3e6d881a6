//! A flat grid (leaves and tiles) regrouped into the tree both formats
//! store: root entries keyed by the origins of their 4096³ regions, each a
//! constant tile or an upper (32³) internal node; upper nodes hold 128³
//! tiles or lower (16³) internal nodes; lower nodes hold 8³ tiles or
//! leaves. Children and tiles are kept by their index in the parent's
//! table, `(x << 2L) | (y << L) | z` of the child's place, which is also the
//! order both formats store them in; root entries are kept in OpenVDB's
//! order (by origin, x first), which NanoVDB's converter keeps too.
//!
//! Building checks what a valid tree needs: node-aligned origins, no
//! duplicates, no tile overlapping a leaf or another tile.

use std::collections::BTreeMap;

use crate::loaders::vdb::{VdbGrid, VdbLeaf};
use crate::{Result, VolumeError};

/// A constant region: its value and whether it is active.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TileValue {
    pub(crate) value: f32,
    pub(crate) active: bool,
}

/// An internal node's entries by table index: tiles, and children.
#[derive(Debug)]
pub(crate) struct Internal<C> {
    pub(crate) origin: [i32; 3],
    pub(crate) tiles: BTreeMap<u32, TileValue>,
    pub(crate) children: BTreeMap<u32, C>,
}

pub(crate) type Lower<'g> = Internal<&'g VdbLeaf>;
pub(crate) type Upper<'g> = Internal<Lower<'g>>;

/// One root entry.
#[derive(Debug)]
pub(crate) enum RootEntry<'g> {
    Tile(TileValue),
    Child(Upper<'g>),
}

/// The grid's tree; leaves are borrowed from the grid.
#[derive(Debug)]
pub(crate) struct Tree<'g> {
    pub(crate) background: f32,
    pub(crate) root: BTreeMap<[i32; 3], RootEntry<'g>>,
}

/// log2 of the edge in voxels of an upper node, a lower node and a leaf.
pub(crate) const UPPER_TOTAL: u32 = 12;
pub(crate) const LOWER_TOTAL: u32 = 7;
pub(crate) const LEAF_TOTAL: u32 = 3;

/// Table index of the child at `p` in a node of edge `2^total` voxels
/// whose children have edge `2^child_total`.
pub(crate) fn child_index(p: [i32; 3], total: u32, child_total: u32) -> u32 {
    let log2 = total - child_total;
    let m = (1i32 << total) - 1;
    let c = p.map(|v| ((v & m) >> child_total) as u32);
    (c[0] << (2 * log2)) | (c[1] << log2) | c[2]
}

/// Origin of the child with table index `i` of a node at `origin`.
pub(crate) fn child_origin(origin: [i32; 3], i: u32, log2: u32, child_total: u32) -> [i32; 3] {
    let m = (1u32 << log2) - 1;
    let c = [i >> (2 * log2), (i >> log2) & m, i & m];
    std::array::from_fn(|k| origin[k].wrapping_add((c[k] as i32) << child_total))
}

fn aligned(p: [i32; 3], total: u32) -> [i32; 3] {
    p.map(|v| v & !((1i32 << total) - 1))
}

fn invalid(g: &VdbGrid, msg: String) -> VolumeError {
    VolumeError::Invalid(format!("grid `{}`: {msg}", g.name))
}

impl<C> Internal<C> {
    fn new(origin: [i32; 3]) -> Self {
        Internal {
            origin,
            tiles: BTreeMap::new(),
            children: BTreeMap::new(),
        }
    }
}

impl<'g> Tree<'g> {
    /// Groups `g`'s leaves and tiles into a tree. Tiles that are inactive
    /// and equal to the background are dropped (they are the background).
    pub(crate) fn build(g: &'g VdbGrid) -> Result<Tree<'g>> {
        let mut t = Tree {
            background: g.background,
            root: BTreeMap::new(),
        };
        for leaf in &g.leaves {
            if aligned(leaf.origin, LEAF_TOTAL) != leaf.origin {
                let o = leaf.origin;
                return Err(invalid(
                    g,
                    format!("leaf origin {o:?} is not a multiple of 8"),
                ));
            }
            let lower = t.lower_at(g, leaf.origin)?;
            let i = child_index(leaf.origin, LOWER_TOTAL, LEAF_TOTAL);
            if lower.tiles.contains_key(&i) || lower.children.insert(i, leaf).is_some() {
                let o = leaf.origin;
                return Err(invalid(
                    g,
                    format!("two leaves or a leaf and a tile at {o:?}"),
                ));
            }
        }
        for tile in &g.tiles {
            if !tile.active && tile.value == g.background {
                continue;
            }
            let v = TileValue {
                value: tile.value,
                active: tile.active,
            };
            t.add_tile(g, tile.origin, tile.size, v)?;
        }
        Ok(t)
    }

    fn upper_at(&mut self, g: &VdbGrid, p: [i32; 3]) -> Result<&mut Upper<'g>> {
        let key = aligned(p, UPPER_TOTAL);
        let entry = self
            .root
            .entry(key)
            .or_insert_with(|| RootEntry::Child(Internal::new(key)));
        match entry {
            RootEntry::Child(u) => Ok(u),
            RootEntry::Tile(_) => Err(invalid(g, format!("root tile at {key:?} overlaps voxels"))),
        }
    }

    fn lower_at(&mut self, g: &VdbGrid, p: [i32; 3]) -> Result<&mut Lower<'g>> {
        let upper = self.upper_at(g, p)?;
        let i = child_index(p, UPPER_TOTAL, LOWER_TOTAL);
        if upper.tiles.contains_key(&i) {
            let o = aligned(p, LOWER_TOTAL);
            return Err(invalid(g, format!("tile at {o:?} overlaps voxels")));
        }
        Ok(upper
            .children
            .entry(i)
            .or_insert_with(|| Internal::new(aligned(p, LOWER_TOTAL))))
    }

    fn add_tile(&mut self, g: &VdbGrid, o: [i32; 3], size: u32, v: TileValue) -> Result<()> {
        let total = match size {
            8 => LEAF_TOTAL,
            128 => LOWER_TOTAL,
            4096 => UPPER_TOTAL,
            _ => return Err(invalid(g, format!("tile of size {size} (8, 128 or 4096)"))),
        };
        let clash = || invalid(g, format!("tile at {o:?} overlaps another tile or voxels"));
        if aligned(o, total) != o {
            return Err(invalid(
                g,
                format!("tile origin {o:?} is not a multiple of {size}"),
            ));
        }
        if total == UPPER_TOTAL {
            return match self.root.insert(o, RootEntry::Tile(v)) {
                None => Ok(()),
                Some(_) => Err(clash()),
            };
        }
        if total == LOWER_TOTAL {
            let upper = self.upper_at(g, o)?;
            let i = child_index(o, UPPER_TOTAL, LOWER_TOTAL);
            if upper.children.contains_key(&i) || upper.tiles.insert(i, v).is_some() {
                return Err(clash());
            }
            return Ok(());
        }
        let lower = self.lower_at(g, o)?;
        let i = child_index(o, LOWER_TOTAL, LEAF_TOTAL);
        if lower.children.contains_key(&i) || lower.tiles.insert(i, v).is_some() {
            return Err(clash());
        }
        Ok(())
    }

    /// Upper nodes in root order.
    pub(crate) fn uppers(&self) -> impl Iterator<Item = &Upper<'g>> {
        self.root.values().filter_map(|e| match e {
            RootEntry::Child(u) => Some(u),
            RootEntry::Tile(_) => None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loaders::vdb::{GridClass, VdbTile};

    fn grid(leaves: &[[i32; 3]], tiles: &[([i32; 3], u32)]) -> VdbGrid {
        VdbGrid {
            name: "g".into(),
            grid_class: GridClass::FogVolume,
            file_version: 224,
            stored_as_half: false,
            compression: "none".into(),
            background: 0.0,
            index_to_world: [
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            leaves: leaves
                .iter()
                .map(|&origin| VdbLeaf {
                    origin,
                    values: Box::new([1.0; 512]),
                    active: [!0; 8],
                })
                .collect(),
            tiles: tiles
                .iter()
                .map(|&(origin, size)| VdbTile {
                    origin,
                    size,
                    value: 2.0,
                    active: true,
                })
                .collect(),
        }
    }

    #[test]
    fn groups_leaves_and_tiles_by_node() {
        let g = grid(
            &[[0, 0, 0], [-8, 0, 0], [8, 16, 24], [4096, 0, 0]],
            &[([128, 0, 0], 128), ([0, 8, 0], 8), ([-8192, 0, 0], 4096)],
        );
        let t = Tree::build(&g).unwrap();
        let keys: Vec<_> = t.root.keys().copied().collect();
        assert_eq!(
            keys,
            [[-8192, 0, 0], [-4096, 0, 0], [0, 0, 0], [4096, 0, 0]]
        );
        let RootEntry::Child(u) = &t.root[&[0, 0, 0]] else {
            panic!()
        };
        assert_eq!(u.children.len(), 1);
        assert_eq!(u.tiles.len(), 1);
        assert_eq!(
            child_origin([0; 3], *u.tiles.keys().next().unwrap(), 5, 7),
            [128, 0, 0]
        );
        let lower = &u.children[&0];
        assert_eq!(lower.children.len(), 2);
        assert_eq!(lower.tiles.len(), 1);
        let i = child_index([8, 16, 24], LOWER_TOTAL, LEAF_TOTAL);
        assert_eq!(child_origin([0; 3], i, 4, 3), [8, 16, 24]);
    }

    #[test]
    fn rejects_invalid_trees() {
        assert!(Tree::build(&grid(&[[1, 0, 0]], &[])).is_err());
        assert!(Tree::build(&grid(&[[0, 0, 0], [0, 0, 0]], &[])).is_err());
        assert!(Tree::build(&grid(&[[0, 0, 0]], &[([0, 0, 0], 8)])).is_err());
        assert!(Tree::build(&grid(&[[0, 0, 0]], &[([0, 0, 0], 4096)])).is_err());
        assert!(Tree::build(&grid(&[], &[([0, 0, 0], 16)])).is_err());
        assert!(Tree::build(&grid(&[], &[([64, 0, 0], 128)])).is_err());
    }
}

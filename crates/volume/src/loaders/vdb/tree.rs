//! Tree topology: root, internal and leaf nodes, flattened into leaves and
//! tiles. Vector grids are read as one tree of `K`-float values and split
//! into one float tree per component, all with the same topology.

use super::grid::{bit_on, for_each_active, FileHeader, GridDesc, Tile, VdbGrid, VdbLeaf, VdbTile};
use super::metadata::{compression_name, read_grid_head};
use super::reader::{grid_context, Reader};
use super::transform::read_transform;
use super::values::{read_compressed_values, read_full, Codec};
use crate::error::Result;

struct LeafTopo {
    origin: [i32; 3],
    mask: [u64; 8],
}

/// One component's flattened tree.
struct Tree {
    background: f32,
    leaves: Vec<VdbLeaf>,
    tiles: Vec<VdbTile>,
}

/// Suffixes of the component grids' names: `vel` → `vel.x`, `vel.y`, `vel.z`.
const AXES: [&str; 3] = ["x", "y", "z"];

/// Reads the grid at `desc.grid_pos`, whose values have `K` floats (1 for
/// `float` grids, 3 for `vec3s`; the caller has checked the type). Returns
/// one float grid per component and the offset just past the grid.
pub(super) fn read_grid_at<const K: usize>(
    r: &mut Reader,
    file: &FileHeader,
    desc: &GridDesc,
) -> Result<([VdbGrid; K], usize)> {
    r.seek(desc.grid_pos, "grid")?;
    let head = read_grid_head(r)?;
    let index_to_world = read_transform(r)?;
    let end;
    let trees = if desc.instance_parent.is_empty() {
        let t = read_tree::<K>(r, head.compression, desc.half)?;
        end = r.offset();
        t
    } else {
        end = r.offset();
        let parent = file
            .descs
            .iter()
            .find(|d| d.unique_name == desc.instance_parent && d.instance_parent.is_empty())
            .ok_or_else(|| {
                r.fail(format!(
                    "instance parent `{}` not found",
                    desc.instance_parent
                ))
            })?;
        if parent.type_name != desc.type_name || parent.half != desc.half {
            return Err(r.fail(format!(
                "instance parent `{}` ({}) does not match the instance's type ({})",
                parent.display_name, parent.type_name, desc.type_name
            )));
        }
        let mut pr = Reader::window(r.path, r.data, r.base, grid_context(&parent.display_name));
        pr.seek(parent.grid_pos, "grid")?;
        let phead = read_grid_head(&mut pr)?;
        read_transform(&mut pr)?;
        read_tree::<K>(&mut pr, phead.compression, parent.half)?
    };
    let mut c = 0;
    let grids = trees.map(|tree| {
        let name = match K {
            1 => desc.name.clone(),
            _ => format!("{}.{}", desc.name, AXES[c]),
        };
        c += 1;
        VdbGrid {
            name,
            grid_class: head.class,
            file_version: file.version,
            stored_as_half: desc.half,
            compression: compression_name(head.compression),
            background: tree.background,
            index_to_world,
            leaves: tree.leaves,
            tiles: tree.tiles,
        }
    });
    Ok((grids, end))
}

fn read_tree<const K: usize>(r: &mut Reader, compression: u32, half: bool) -> Result<[Tree; K]> {
    // Trees once held several buffers; OpenVDB only warns when this is not 1.
    let _buffer_count = r.i32("tree buffer count")?;
    // `sizeof(ValueType)` bytes even in half-float grids, like root tiles.
    let background: [f32; K] = read_full(r, "background value")?;
    let num_tiles = r.u32("root tile count")? as usize;
    let num_children = r.u32("root child count")? as usize;
    // origin + value + active flag
    let tile_bytes = 12 + 4 * K + 1;
    // origin + two 32³ masks + at least the per-node metadata byte
    const CHILD_MIN_BYTES: usize = 12 + 2 * 4096 + 1;
    if num_tiles > r.remaining() / tile_bytes {
        return Err(r.fail(format!("implausible root tile count {num_tiles}")));
    }
    let all_tile_bytes = num_tiles * tile_bytes;
    if num_children > (r.remaining() - all_tile_bytes) / CHILD_MIN_BYTES {
        return Err(r.fail(format!("implausible root child count {num_children}")));
    }
    let codec = Codec {
        compression,
        half,
        background,
    };
    let mut tiles = Vec::new();
    for _ in 0..num_tiles {
        let origin = r.coord("root tile")?.map(|v| v & !4095);
        let value = read_full(r, "root tile value")?;
        let active = r.u8("root tile state")? != 0;
        if active || value != background {
            tiles.push(Tile {
                origin,
                size: 4096,
                value,
                active,
            });
        }
    }
    let mut leaf_topos = Vec::new();
    let mut origins = std::collections::HashSet::new();
    for _ in 0..num_children {
        let at = r.offset();
        let origin = r.coord("root child origin")?.map(|v| v & !4095);
        if !origins.insert(origin) {
            return Err(r.fail_at(at, format!("duplicate root child at {origin:?}")));
        }
        read_internal(r, &codec, origin, 5, &mut tiles, &mut leaf_topos)?;
    }
    let leaves = read_leaf_buffers(r, &codec, leaf_topos)?;
    let mut leaves = leaves.into_iter();
    Ok(std::array::from_fn(|c| Tree {
        background: background[c],
        leaves: leaves.next().unwrap_or_default(),
        tiles: tiles.iter().map(|t| t.component(c)).collect(),
    }))
}

/// The leaves' value buffers, which follow the topology in the same
/// depth-first order, one leaf list per channel.
fn read_leaf_buffers<const K: usize>(
    r: &mut Reader,
    codec: &Codec<K>,
    leaf_topos: Vec<LeafTopo>,
) -> Result<[Vec<VdbLeaf>; K]> {
    let mut leaves: [Vec<VdbLeaf>; K] = std::array::from_fn(|_| Vec::new());
    let mut buf = vec![0.0f32; 512 * K];
    for topo in leaf_topos {
        // OpenVDB seeks over this copy of the mask and keeps the topology's.
        r.take(64, "leaf value mask")?;
        let what = format!("leaf buffer at {:?}", topo.origin);
        read_compressed_values(r, codec, &mut buf, &topo.mask, &what)?;
        for (c, list) in leaves.iter_mut().enumerate() {
            let mut values = Box::new([0.0f32; 512]);
            for (v, &src) in values.iter_mut().zip(buf.iter().skip(c).step_by(K)) {
                *v = src;
            }
            list.push(VdbLeaf {
                origin: topo.origin,
                values,
                active: topo.mask,
            });
        }
    }
    Ok(leaves)
}

/// Reads the topology of a 32³ (`level` 5) or 16³ (`level` 4) internal node:
/// child mask, value mask, the tile values, then each child in index order.
fn read_internal<const K: usize>(
    r: &mut Reader,
    codec: &Codec<K>,
    origin: [i32; 3],
    level: u32,
    tiles: &mut Vec<Tile<K>>,
    leaves: &mut Vec<LeafTopo>,
) -> Result<()> {
    let log2 = level;
    let child_log2 = if level == 5 { 7 } else { 3 };
    let n = 1usize << (3 * log2);
    let child_mask = r.mask(n / 64, "internal node child mask")?;
    let value_mask = r.mask(n / 64, "internal node value mask")?;
    let mut values = vec![0.0f32; n * K];
    let what = format!("tile values of internal node at {origin:?}");
    read_compressed_values(r, codec, &mut values, &value_mask, &what)?;
    let dim_mask = (1usize << log2) - 1;
    let child_origin = |idx: usize| {
        let x = (idx >> (2 * log2)) as i32;
        let y = ((idx >> log2) & dim_mask) as i32;
        let z = (idx & dim_mask) as i32;
        [
            origin[0].wrapping_add(x << child_log2),
            origin[1].wrapping_add(y << child_log2),
            origin[2].wrapping_add(z << child_log2),
        ]
    };
    for (idx, value) in values.chunks_exact(K).enumerate() {
        if bit_on(&child_mask, idx) {
            continue;
        }
        let active = bit_on(&value_mask, idx);
        // A tile is kept in every component when any component differs
        // from the background, so the components share one topology.
        if active || value != codec.background {
            let mut v = [0.0f32; K];
            v.copy_from_slice(value);
            tiles.push(Tile {
                origin: child_origin(idx),
                size: 1 << child_log2,
                value: v,
                active,
            });
        }
    }
    let mut result = Ok(());
    for_each_active(&child_mask, |idx| {
        if result.is_err() {
            return;
        }
        let o = child_origin(idx);
        result = if level == 5 {
            read_internal(r, codec, o, 4, tiles, leaves)
        } else {
            r.mask(8, "leaf value mask").map(|m| {
                let mut mask = [0u64; 8];
                mask.copy_from_slice(&m);
                leaves.push(LeafTopo { origin: o, mask });
            })
        };
    });
    result
}

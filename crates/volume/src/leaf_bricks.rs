//! A brick grid assembled from 8³ leaves that arrive one at a time, each
//! stored in its final precision as it arrives, for readers that stream a
//! file's leaves instead of holding them: the voxels never exist in f32
//! beyond one run of leaves, and the final data array is allocated once.
//!
//! The result is bit for bit what [`BrickGridBuilder::adopt`] of every
//! leaf followed by [`BrickGridBuilder::finish_converted`] gives (same
//! table, constants and data order), because every leaf brick and every
//! brick the builder already wrote in f32 gets its place in the data array
//! up front, in brick order, and bricks that turn out constant are squeezed
//! out at the end.

use std::collections::HashMap;
use std::sync::Arc;

use crate::grid::{BrickContent, BrickGrid, Voxel, BRICK_VOXELS, CONSTANT};
use crate::grid_builder::{convert_brick, BrickGridBuilder};

const NO_SLOT: u32 = u32::MAX;

#[derive(Clone, Copy)]
enum Slot {
    /// Not written yet (a leaf still to come, or a brick of the builder's).
    Open,
    Data,
    Constant(f32),
}

pub(crate) struct LeafBricks<T> {
    dims: [u32; 3],
    bdims: [u32; 3],
    /// The builder's bricks written in f32 (by tiles) and every brick's constant.
    bricks: Vec<Option<Box<[f32; BRICK_VOXELS]>>>,
    constant: Vec<f32>,
    /// Per brick, its place in `data` (in units of bricks), or `NO_SLOT`.
    slot: Vec<u32>,
    state: Vec<Slot>,
    data: Arc<[T]>,
}

impl<T: Voxel> LeafBricks<T> {
    /// The bricks of `builder` (its tiles written) and places for the leaves
    /// that will fill the bricks `leaf_bricks`.
    pub(crate) fn new(builder: BrickGridBuilder, leaf_bricks: &[usize]) -> Self {
        let (dims, bdims, bricks, constant) = builder.into_parts();
        let mut slot = vec![NO_SLOT; bricks.len()];
        for &b in leaf_bricks {
            slot[b] = 0;
        }
        for (b, brick) in bricks.iter().enumerate() {
            if brick.is_some() {
                slot[b] = 0;
            }
        }
        let mut n = 0u32;
        for s in slot.iter_mut().filter(|s| **s != NO_SLOT) {
            *s = n;
            n += 1;
        }
        // Collected from a sized iterator: one allocation, no copy.
        let data: Arc<[T]> = (0..n as usize * BRICK_VOXELS)
            .map(|_| T::store(0.0))
            .collect();
        LeafBricks {
            dims,
            bdims,
            bricks,
            constant,
            slot,
            state: vec![Slot::Open; n as usize],
            data,
        }
    }

    pub(crate) fn dims(&self) -> ([u32; 3], [u32; 3]) {
        (self.dims, self.bdims)
    }

    /// Stores brick `b`'s content, converted by [`convert_brick`] from a
    /// leaf (a later leaf of the same brick replaces an earlier one, as
    /// `adopt` does). `b` must be one of the `leaf_bricks` given to `new`.
    pub(crate) fn put(&mut self, b: usize, content: BrickContent<T>) {
        let s = self.slot[b] as usize;
        self.bricks[b] = None;
        self.state[s] = match content {
            BrickContent::Constant(v) => Slot::Constant(v),
            BrickContent::Data(values) => {
                self.data_mut()[s * BRICK_VOXELS..(s + 1) * BRICK_VOXELS].copy_from_slice(&values);
                Slot::Data
            }
        };
    }

    fn data_mut(&mut self) -> &mut [T] {
        Arc::get_mut(&mut self.data).expect("the data array is not shared while it is built")
    }

    /// The grid, bricks not written by a leaf finished as `finish_converted`
    /// finishes them with the map `f`.
    pub(crate) fn finish(mut self, f: impl Fn(f32) -> f32) -> BrickGrid<T> {
        let (dims, bdims) = (self.dims, self.bdims);
        let mut table = Vec::with_capacity(self.slot.len());
        let mut constants: Vec<f32> = Vec::new();
        let mut constant_index: HashMap<u32, u32> = HashMap::new();
        let mut cursor = 0usize;
        for b in 0..self.slot.len() {
            let s = self.slot[b] as usize;
            let content = match self.state.get(s) {
                Some(Slot::Data) => {
                    // Places are in brick order and only shrink: `cursor <= s`.
                    let from = s * BRICK_VOXELS;
                    self.data_mut()
                        .copy_within(from..from + BRICK_VOXELS, cursor * BRICK_VOXELS);
                    None
                }
                Some(Slot::Constant(v)) => Some(BrickContent::Constant(*v)),
                _ => {
                    let brick = self.bricks[b].take();
                    Some(convert_brick(
                        b,
                        dims,
                        bdims,
                        brick.as_deref(),
                        self.constant[b],
                        &f,
                    ))
                }
            };
            match content {
                Some(BrickContent::Constant(v)) => {
                    let k = *constant_index.entry(v.to_bits()).or_insert_with(|| {
                        constants.push(v);
                        (constants.len() - 1) as u32
                    });
                    table.push(CONSTANT | k);
                    continue;
                }
                Some(BrickContent::Data(values)) => {
                    self.data_mut()[cursor * BRICK_VOXELS..(cursor + 1) * BRICK_VOXELS]
                        .copy_from_slice(&values);
                }
                None => {}
            }
            table.push(cursor as u32);
            cursor += 1;
        }
        let used = cursor * BRICK_VOXELS;
        // Leaves that turned out constant leave places unused at the end:
        // the data is copied to its size only then.
        let data = if used == self.data.len() {
            self.data
        } else {
            Arc::from(&self.data[..used])
        };
        BrickGrid::from_parts(dims, bdims, table, constants, data)
    }
}

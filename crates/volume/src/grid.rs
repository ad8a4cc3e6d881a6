//! Sparse brick grid: the one storage layout for dense scalar volumes, chosen
//! to upload unchanged to the GPU.
//!
//! The grid is cut into 8³ bricks (the size of an OpenVDB leaf, so a leaf
//! becomes one brick). A flat `table` has one `u32` per brick: either the
//! offset of the brick's 512 values in `data`, or `CONSTANT | k`, meaning every
//! voxel equals `constants[k]`. Empty space (background) and constant tiles
//! therefore cost 4 bytes per brick; a 1024³ grid at 20 % occupancy needs
//! ≈ 0.2 · 2 bytes per voxel in f16 plus an 8 MiB table.
//!
//! Index convention: voxel `(i, j, k)` is the cell `[i, i+1) × [j, j+1) × [k, k+1)`
//! and its value sits at the cell centre `(i + ½, j + ½, k + ½)`. The field is
//! defined on `[0, dims]` and lookups clamp to the border voxels (Mitsuba's
//! convention; loaders that need a background pad the grid by one voxel of
//! background so clamping reproduces it).

use crate::{Result, VolumeError};
use half::f16;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

pub const BRICK_LOG2: u32 = 3;
pub const BRICK: u32 = 1 << BRICK_LOG2;
pub const BRICK_VOXELS: usize = (BRICK * BRICK * BRICK) as usize;
/// Table entries with this bit set index `constants` instead of `data`.
pub const CONSTANT: u32 = 1 << 31;
/// Largest number of bricks a grid may have (a 4096³ grid): the table must
/// stay a plain array that the GPU can bind.
pub const MAX_BRICKS: u64 = 1 << 27;

/// Storage type of a voxel value.
pub trait Voxel: Copy + Send + Sync + 'static {
    const NAME: &'static str;
    /// How SIMD lanes read this type (`lanes.rs`): bits per voxel, 32 for
    /// IEEE single, 16 for IEEE half, 0 for none.
    const LANE_BITS: u32;
    fn load(self) -> f32;
    fn store(x: f32) -> Self;
}

impl Voxel for f32 {
    const NAME: &'static str = "f32";
    const LANE_BITS: u32 = 32;
    #[inline]
    fn load(self) -> f32 {
        self
    }
    #[inline]
    fn store(x: f32) -> Self {
        x
    }
}

impl Voxel for f16 {
    const NAME: &'static str = "f16";
    const LANE_BITS: u32 = 16;
    #[inline]
    fn load(self) -> f32 {
        self.to_f32()
    }
    #[inline]
    fn store(x: f32) -> Self {
        f16::from_f32(x)
    }
}

/// Storage precision chosen per medium.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Precision {
    #[default]
    F16,
    F32,
}

#[derive(Clone, Debug)]
pub struct BrickGrid<T> {
    dims: [u32; 3],
    bdims: [u32; 3],
    // Shared: a clone (an instance of the medium, a frame's copy) costs no
    // voxel memory.
    table: Arc<[u32]>,
    constants: Arc<[f32]>,
    data: Arc<[T]>,
}

/// Validates grid dimensions before anything is allocated.
pub fn check_dims(dims: [u64; 3]) -> Result<[u32; 3]> {
    if dims.iter().any(|&d| d == 0 || d > 1 << 16) {
        return Err(VolumeError::Invalid(format!(
            "grid dimensions {}×{}×{} out of range (each must be 1..=65536)",
            dims[0], dims[1], dims[2]
        )));
    }
    let bricks: u64 = dims.iter().map(|&d| d.div_ceil(BRICK as u64)).product();
    if bricks > MAX_BRICKS {
        return Err(VolumeError::Invalid(format!(
            "grid dimensions {}×{}×{} need {} bricks, more than the limit of {}",
            dims[0], dims[1], dims[2], bricks, MAX_BRICKS
        )));
    }
    Ok([dims[0] as u32, dims[1] as u32, dims[2] as u32])
}

pub(crate) fn brick_dims(dims: [u32; 3]) -> [u32; 3] {
    dims.map(|d| d.div_ceil(BRICK))
}

#[inline]
pub(crate) fn local_index(i: u32, j: u32, k: u32) -> usize {
    let m = BRICK - 1;
    (((k & m) << (2 * BRICK_LOG2)) | ((j & m) << BRICK_LOG2) | (i & m)) as usize
}

pub(crate) enum BrickContent<T> {
    Constant(f32),
    Data(Vec<T>),
}

/// The values of brick `b` (x fastest in brick order), `f` read at voxel
/// indices inside `dims`: voxels past the grid edge copy the clamped border,
/// so that constant-brick detection is not fooled by padding.
pub(crate) fn brick_values(
    b: usize,
    dims: [u32; 3],
    bdims: [u32; 3],
    f: &impl Fn(u32, u32, u32) -> f32,
) -> [f32; BRICK_VOXELS] {
    let bx = (b % bdims[0] as usize) as u32;
    let by = ((b / bdims[0] as usize) % bdims[1] as usize) as u32;
    let bz = (b / (bdims[0] as usize * bdims[1] as usize)) as u32;
    let mut values = [0.0f32; BRICK_VOXELS];
    for lk in 0..BRICK {
        for lj in 0..BRICK {
            for li in 0..BRICK {
                let (i, j, k) = (bx * BRICK + li, by * BRICK + lj, bz * BRICK + lk);
                values[local_index(li, lj, lk)] =
                    f(i.min(dims[0] - 1), j.min(dims[1] - 1), k.min(dims[2] - 1));
            }
        }
    }
    values
}

pub(crate) fn classify<T: Voxel>(values: &[f32]) -> BrickContent<T> {
    let first = values[0];
    if values.iter().all(|v| v.to_bits() == first.to_bits()) {
        BrickContent::Constant(T::store(first).load())
    } else {
        BrickContent::Data(values.iter().map(|&v| T::store(v)).collect())
    }
}

impl<T: Voxel> BrickGrid<T> {
    /// Evaluates `f` at every voxel, brick by brick in parallel, eliding
    /// constant bricks. `f` receives voxel indices inside `dims`.
    pub fn from_fn(dims: [u32; 3], f: impl Fn(u32, u32, u32) -> f32 + Sync) -> Result<Self> {
        let dims = check_dims(dims.map(u64::from))?;
        let bdims = brick_dims(dims);
        let n = bdims.iter().map(|&b| b as usize).product::<usize>();
        let bricks: Vec<BrickContent<T>> = (0..n)
            .into_par_iter()
            .map(|b| classify::<T>(&brick_values(b, dims, bdims, &f)))
            .collect();
        Ok(Self::assemble(dims, bdims, bricks))
    }

    /// This grid stored as `U`: exactly `BrickGrid::<U>::from_fn(dims, |i,
    /// j, k| self.fetch(i, j, k))` (same table, constants and data), but a
    /// constant brick is converted without reading its voxels, so a sparse
    /// grid converts in time proportional to its data bricks, not its box.
    pub fn to_voxel<U: Voxel>(&self) -> BrickGrid<U> {
        let (dims, bdims) = (self.dims, self.bdims);
        let n = self.table.len();
        let bricks: Vec<BrickContent<U>> = (0..n)
            .into_par_iter()
            .map(|b| {
                let entry = self.table[b];
                if entry & CONSTANT != 0 {
                    // from_fn would read 512 equal values: a constant brick.
                    let c = self.constants[(entry & !CONSTANT) as usize];
                    return BrickContent::Constant(U::store(c).load());
                }
                let fetch = |i, j, k| self.fetch_in_grid(i, j, k);
                classify::<U>(&brick_values(b, dims, bdims, &fetch))
            })
            .collect();
        BrickGrid::assemble(dims, bdims, bricks)
    }

    /// A grid from its table, constants and data, as [`Self::assemble`]
    /// lays them out (the caller keeps that layout).
    pub(crate) fn from_parts(
        dims: [u32; 3],
        bdims: [u32; 3],
        table: Vec<u32>,
        constants: Vec<f32>,
        data: Arc<[T]>,
    ) -> Self {
        BrickGrid {
            dims,
            bdims,
            table: table.into(),
            constants: constants.into(),
            data,
        }
    }

    pub(crate) fn assemble(dims: [u32; 3], bdims: [u32; 3], bricks: Vec<BrickContent<T>>) -> Self {
        let mut table = Vec::with_capacity(bricks.len());
        let mut constants: Vec<f32> = Vec::new();
        let mut constant_index: HashMap<u32, u32> = HashMap::new();
        let dense = bricks
            .iter()
            .filter(|b| matches!(b, BrickContent::Data(_)))
            .count();
        let mut data = Vec::with_capacity(dense * BRICK_VOXELS);
        for brick in bricks {
            match brick {
                BrickContent::Constant(v) => {
                    let k = *constant_index.entry(v.to_bits()).or_insert_with(|| {
                        constants.push(v);
                        (constants.len() - 1) as u32
                    });
                    table.push(CONSTANT | k);
                }
                BrickContent::Data(values) => {
                    table.push((data.len() / BRICK_VOXELS) as u32);
                    data.extend_from_slice(&values);
                }
            }
        }
        BrickGrid {
            dims,
            bdims,
            table: table.into(),
            constants: constants.into(),
            data: data.into(),
        }
    }

    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    /// The value of every voxel in the inclusive index box `[lo, hi]`, read
    /// with clamped indices as `fetch` reads them, when the bricks it
    /// touches are all constant with one value; `None` otherwise (also when
    /// they are equal but stored as data). One table lookup per brick: the
    /// sparse super-voxel build skips empty space with it.
    pub fn uniform_in(&self, lo: [i32; 3], hi: [i32; 3]) -> Option<f32> {
        let b: [(u32, u32); 3] = std::array::from_fn(|a| {
            let last = self.dims[a] as i32 - 1;
            let (l, h) = (lo[a].clamp(0, last) as u32, hi[a].clamp(0, last) as u32);
            (l >> BRICK_LOG2, h >> BRICK_LOG2)
        });
        let mut value: Option<u32> = None;
        for bz in b[2].0..=b[2].1 {
            for by in b[1].0..=b[1].1 {
                for bx in b[0].0..=b[0].1 {
                    let entry =
                        self.table[((bz * self.bdims[1] + by) * self.bdims[0] + bx) as usize];
                    if entry & CONSTANT == 0 {
                        return None;
                    }
                    let v = self.constants[(entry & !CONSTANT) as usize].to_bits();
                    if *value.get_or_insert(v) != v {
                        return None;
                    }
                }
            }
        }
        value.map(f32::from_bits)
    }

    /// Whether `other` stores the same bits: dimensions, brick table,
    /// constants and voxel data in the same order.
    pub fn bit_identical(&self, other: &Self) -> bool {
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        self.dims == other.dims
            && self.table == other.table
            && bits(&self.constants) == bits(&other.constants)
            && self.data.len() == other.data.len()
            && self
                .data
                .iter()
                .zip(other.data.iter())
                .all(|(a, b)| a.load().to_bits() == b.load().to_bits())
    }

    /// The raw storage for the SIMD lanes of `lanes.rs`: (brick dims, brick
    /// table, constants, voxel data).
    #[inline(always)]
    pub(crate) fn raw(&self) -> ([u32; 3], &[u32], &[f32], &[T]) {
        (self.bdims, &self.table, &self.constants, &self.data)
    }

    /// Value of voxel `(i, j, k)`, with indices clamped to the grid.
    #[inline(always)]
    pub fn fetch(&self, i: i32, j: i32, k: i32) -> f32 {
        let i = i.clamp(0, self.dims[0] as i32 - 1) as u32;
        let j = j.clamp(0, self.dims[1] as i32 - 1) as u32;
        let k = k.clamp(0, self.dims[2] as i32 - 1) as u32;
        // SAFETY-free indexing: indices are clamped above, so the lookups
        // in `fetch_in_grid` never fail.
        self.fetch_in_grid(i, j, k)
    }

    /// Value of voxel `(i, j, k)`, which the caller has already clamped into
    /// the grid (`i < dims[0]` etc.); the same value `fetch` returns there.
    #[inline(always)]
    pub(crate) fn fetch_in_grid(&self, i: u32, j: u32, k: u32) -> f32 {
        let b = ((k >> BRICK_LOG2) * self.bdims[1] + (j >> BRICK_LOG2)) * self.bdims[0]
            + (i >> BRICK_LOG2);
        let entry = self.table[b as usize];
        if entry & CONSTANT != 0 {
            self.constants[(entry & !CONSTANT) as usize]
        } else {
            self.data[entry as usize * BRICK_VOXELS + local_index(i, j, k)].load()
        }
    }

    /// The eight voxels `(i + di, j + dj, k + dk)`, `d* ∈ {0, 1}`, in the
    /// order 000, 100, 010, 110, 001, 101, 011, 111, when all eight lie in
    /// one brick and inside the grid (no clamping needed); `None` otherwise.
    /// One table lookup instead of eight: the trilinear fast path.
    #[inline(always)]
    pub(crate) fn corners_in_brick(&self, i: u32, j: u32, k: u32) -> Option<[f32; 8]> {
        let m = BRICK - 1;
        // `i < dims − 1` keeps the upper corner inside the grid, `i & m != m`
        // inside the brick (dims ≥ 1, so `dims − 1` cannot underflow).
        let inside = i < self.dims[0] - 1
            && j < self.dims[1] - 1
            && k < self.dims[2] - 1
            && ((i & m) != m)
            && ((j & m) != m)
            && ((k & m) != m);
        if !inside {
            return None;
        }
        let b = ((k >> BRICK_LOG2) * self.bdims[1] + (j >> BRICK_LOG2)) * self.bdims[0]
            + (i >> BRICK_LOG2);
        let entry = self.table[b as usize];
        if entry & CONSTANT != 0 {
            return Some([self.constants[(entry & !CONSTANT) as usize]; 8]);
        }
        const DY: usize = BRICK as usize;
        const DZ: usize = (BRICK * BRICK) as usize;
        let base = entry as usize * BRICK_VOXELS + local_index(i, j, k);
        // One bounds check for the whole 2×2×2 block.
        let d = &self.data[base..base + DZ + DY + 2];
        Some([
            d[0].load(),
            d[1].load(),
            d[DY].load(),
            d[DY + 1].load(),
            d[DZ].load(),
            d[DZ + 1].load(),
            d[DZ + DY].load(),
            d[DZ + DY + 1].load(),
        ])
    }

    /// Bytes held by the grid (table, constants and brick data).
    pub fn memory_bytes(&self) -> usize {
        self.table.len() * 4 + self.constants.len() * 4 + self.data.len() * std::mem::size_of::<T>()
    }

    pub fn dense_bricks(&self) -> usize {
        self.data.len() / BRICK_VOXELS
    }

    pub fn brick_count(&self) -> usize {
        self.table.len()
    }

    /// Flat buffers for upload: table, constants, brick values.
    pub fn buffers(&self) -> (&[u32], &[f32], &[T]) {
        (&self.table, &self.constants, &self.data)
    }

    /// Applies `f` to every stored value (bricks and constants) in place of a
    /// full rebuild; used for level-set → fog conversion and clamping.
    pub fn map_values(&self, f: impl Fn(f32) -> f32 + Sync) -> Self {
        BrickGrid {
            dims: self.dims,
            bdims: self.bdims,
            table: self.table.clone(),
            constants: self
                .constants
                .iter()
                .map(|&v| T::store(f(v)).load())
                .collect::<Vec<_>>()
                .into(),
            data: self
                .data
                .par_iter()
                .map(|&v| T::store(f(v.load())))
                .collect::<Vec<_>>()
                .into(),
        }
    }
}

#[cfg(test)]
mod grid_test {
    use super::*;

    #[test]
    fn from_fn_round_trips_and_elides_constant_bricks() {
        let g = BrickGrid::<f32>::from_fn([20, 9, 17], |i, j, k| {
            if i < 8 {
                0.0
            } else {
                (i + 100 * j + 10_000 * k) as f32
            }
        })
        .unwrap();
        for k in 0..17 {
            for j in 0..9 {
                for i in 0..20 {
                    let e = if i < 8 {
                        0.0
                    } else {
                        (i + 100 * j + 10_000 * k) as f32
                    };
                    assert_eq!(g.fetch(i, j, k), e);
                }
            }
        }
        // Bricks with i < 8 are constant zero.
        assert_eq!(g.dense_bricks(), 2 * 2 * 3);
        assert_eq!(g.fetch(-5, 3, 3), g.fetch(0, 3, 3));
        assert_eq!(g.fetch(25, 3, 3), g.fetch(19, 3, 3));
    }

    #[test]
    fn rejects_absurd_dimensions_before_allocating() {
        assert!(check_dims([0, 4, 4]).is_err());
        assert!(check_dims([1 << 17, 4, 4]).is_err());
        assert!(check_dims([65536, 65536, 65536]).is_err());
        assert!(check_dims([1024, 1024, 1024]).is_ok());
    }

    #[test]
    fn sparse_1024_cube_stays_small() {
        // 20 % occupancy: a dense slab of 1024×1024×205 voxels.
        let g = BrickGrid::<f16>::from_fn([1024, 1024, 1024], |i, j, k| {
            if k < 205 {
                0.5 + ((i ^ j) & 1) as f32 * 0.25
            } else {
                0.0
            }
        })
        .unwrap();
        let voxels = 1024f64 * 1024.0 * 1024.0;
        let bytes_per_voxel = g.memory_bytes() as f64 / voxels;
        assert!(bytes_per_voxel < 0.5, "{bytes_per_voxel} bytes per voxel");
    }
}

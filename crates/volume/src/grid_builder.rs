//! Incremental construction of a [`BrickGrid`] from sparse input (OpenVDB
//! leaves and tiles): every brick starts as a constant and is materialised
//! in f32 on first write; a whole 8³ block (an OpenVDB leaf) is adopted
//! without a copy. `finish_converted` maps the values and stores them in
//! the final precision in one pass, so a file's voxels exist in f32 once.

use crate::grid::{
    brick_dims, brick_values, check_dims, classify, local_index, BrickContent, BrickGrid, Voxel,
    BRICK, BRICK_LOG2, BRICK_VOXELS,
};
use crate::Result;
use rayon::prelude::*;

/// Incremental construction from sparse input (OpenVDB leaves and tiles):
/// every brick starts as a constant and is materialised in f32 on first write.
pub struct BrickGridBuilder {
    dims: [u32; 3],
    bdims: [u32; 3],
    bricks: Vec<Option<Box<[f32; BRICK_VOXELS]>>>,
    constant: Vec<f32>,
}

impl BrickGridBuilder {
    pub fn new(dims: [u64; 3], background: f32) -> Result<Self> {
        let dims = check_dims(dims)?;
        let bdims = brick_dims(dims);
        let n = bdims.iter().map(|&b| b as usize).product::<usize>();
        Ok(BrickGridBuilder {
            dims,
            bdims,
            bricks: vec![None; n],
            constant: vec![background; n],
        })
    }

    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    fn brick_index(&self, b: [u32; 3]) -> usize {
        ((b[2] * self.bdims[1] + b[1]) * self.bdims[0] + b[0]) as usize
    }

    fn brick_mut(&mut self, b: usize) -> &mut [f32; BRICK_VOXELS] {
        let c = self.constant[b];
        self.bricks[b].get_or_insert_with(|| Box::new([c; BRICK_VOXELS]))
    }

    /// Sets one voxel; indices outside the grid are ignored.
    pub fn set(&mut self, i: i64, j: i64, k: i64, v: f32) {
        if i < 0 || j < 0 || k < 0 {
            return;
        }
        let (i, j, k) = (i as u64, j as u64, k as u64);
        if i >= self.dims[0] as u64 || j >= self.dims[1] as u64 || k >= self.dims[2] as u64 {
            return;
        }
        let (i, j, k) = (i as u32, j as u32, k as u32);
        let b = self.brick_index([i >> BRICK_LOG2, j >> BRICK_LOG2, k >> BRICK_LOG2]);
        self.brick_mut(b)[local_index(i, j, k)] = v;
    }

    /// Fills the inclusive voxel box `lo..=hi` (clipped to the grid) with `v`.
    /// Whole bricks become constants without allocating.
    pub fn fill(&mut self, lo: [i64; 3], hi: [i64; 3], v: f32) {
        let lo: [u32; 3] = std::array::from_fn(|a| lo[a].clamp(0, self.dims[a] as i64) as u32);
        let hi: [i64; 3] = std::array::from_fn(|a| hi[a].min(self.dims[a] as i64 - 1));
        if (0..3).any(|a| hi[a] < lo[a] as i64) {
            return;
        }
        let hi = hi.map(|h| h as u32);
        for bz in lo[2] >> BRICK_LOG2..=hi[2] >> BRICK_LOG2 {
            for by in lo[1] >> BRICK_LOG2..=hi[1] >> BRICK_LOG2 {
                for bx in lo[0] >> BRICK_LOG2..=hi[0] >> BRICK_LOG2 {
                    let b0 = [bx, by, bz].map(|c| c << BRICK_LOG2);
                    let full = (0..3).all(|a| {
                        lo[a] <= b0[a] && (hi[a] >= b0[a] + BRICK - 1 || hi[a] == self.dims[a] - 1)
                    });
                    let b = self.brick_index([bx, by, bz]);
                    if full {
                        self.bricks[b] = None;
                        self.constant[b] = v;
                        continue;
                    }
                    let brick = self.brick_mut(b);
                    for k in lo[2].max(b0[2])..=hi[2].min(b0[2] + BRICK - 1) {
                        for j in lo[1].max(b0[1])..=hi[1].min(b0[1] + BRICK - 1) {
                            for i in lo[0].max(b0[0])..=hi[0].min(b0[0] + BRICK - 1) {
                                brick[local_index(i, j, k)] = v;
                            }
                        }
                    }
                }
            }
        }
    }

    pub fn finish<T: Voxel>(self) -> BrickGrid<T> {
        let dims = self.dims;
        let bdims = self.bdims;
        let contents: Vec<BrickContent<T>> = self
            .bricks
            .into_par_iter()
            .zip(self.constant.into_par_iter())
            .map(|(brick, c)| match brick {
                None => BrickContent::Constant(T::store(c).load()),
                Some(values) => classify::<T>(&values[..]),
            })
            .collect();
        BrickGrid::assemble(dims, bdims, contents)
    }

    /// Makes the 8³ block at voxel `lo` (values in brick order, x fastest)
    /// the brick's content without copying when `lo` starts a brick that
    /// lies wholly inside the grid (every OpenVDB leaf does); otherwise
    /// writes it voxel by voxel with [`Self::set`]. Either way the result
    /// is what 512 `set` calls give.
    pub fn adopt(&mut self, lo: [i64; 3], values: Box<[f32; BRICK_VOXELS]>) {
        if let Some(b) = self.aligned_brick(lo) {
            self.bricks[b] = Some(values);
            return;
        }
        for k in 0..BRICK {
            for j in 0..BRICK {
                for i in 0..BRICK {
                    let v = values[local_index(i, j, k)];
                    self.set(lo[0] + i as i64, lo[1] + j as i64, lo[2] + k as i64, v);
                }
            }
        }
    }

    /// `finish::<f32>().map_values(f).to_voxel::<T>()`, bit for bit, in one
    /// pass: each f32 brick is mapped and stored as `T` and then freed, so
    /// the voxels never exist in f32 twice (a 1024³ sparse VDB's peak
    /// memory; `volume/tests` holds the equality).
    pub fn finish_converted<T: Voxel>(self, f: impl Fn(f32) -> f32 + Sync) -> BrickGrid<T> {
        let (dims, bdims) = (self.dims, self.bdims);
        let contents: Vec<BrickContent<T>> = self
            .bricks
            .into_par_iter()
            .zip(self.constant.into_par_iter())
            .enumerate()
            .map(|(b, (brick, c))| convert_brick(b, dims, bdims, brick.as_deref(), c, &f))
            .collect();
        BrickGrid::assemble(dims, bdims, contents)
    }

    /// The brick that an 8³ block at voxel `lo` fills exactly ([`Self::adopt`]
    /// without a copy), if it does.
    pub(crate) fn aligned_brick(&self, lo: [i64; 3]) -> Option<usize> {
        let aligned = (0..3).all(|a| {
            lo[a] >= 0 && lo[a] % BRICK as i64 == 0 && lo[a] + BRICK as i64 <= self.dims[a] as i64
        });
        aligned.then(|| self.brick_index(lo.map(|v| (v >> BRICK_LOG2) as u32)))
    }

    /// Sizes, the bricks written in f32 so far, and every brick's constant.
    #[allow(clippy::type_complexity)]
    pub(crate) fn into_parts(
        self,
    ) -> (
        [u32; 3],
        [u32; 3],
        Vec<Option<Box<[f32; BRICK_VOXELS]>>>,
        Vec<f32>,
    ) {
        (self.dims, self.bdims, self.bricks, self.constant)
    }
}

/// Brick `b` of a builder as [`BrickGridBuilder::finish_converted`] stores
/// it: `f` of its constant `c`, or of its f32 values `brick`.
pub(crate) fn convert_brick<T: Voxel>(
    b: usize,
    dims: [u32; 3],
    bdims: [u32; 3],
    brick: Option<&[f32; BRICK_VOXELS]>,
    c: f32,
    f: &impl Fn(f32) -> f32,
) -> BrickContent<T> {
    let Some(values) = brick else {
        return BrickContent::Constant(T::store(f(c)).load());
    };
    // finish: 512 equal values are a constant (then mapped and stored).
    let v0 = values[0];
    if values.iter().all(|v| v.to_bits() == v0.to_bits()) {
        return BrickContent::Constant(T::store(f(v0)).load());
    }
    // to_voxel of the mapped grid: voxels past the grid's edge read the
    // clamped border, which lies in the same brick.
    let mapped = values.map(f);
    classify::<T>(&brick_values(b, dims, bdims, &|i, j, k| {
        mapped[local_index(i, j, k)]
    }))
}

#[cfg(test)]
mod grid_builder_test {
    use super::*;
    use half::f16;

    #[test]
    fn to_voxel_equals_from_fn_of_fetch() {
        // Partial edge bricks whose padding differs from the border, empty
        // space, a constant slab and dense data.
        let mut b = BrickGridBuilder::new([21, 10, 17], 0.0).unwrap();
        b.fill([0, 0, 9], [20, 9, 16], 0.25);
        for (i, j, k) in [(3, 4, 5), (20, 9, 16), (17, 0, 2), (8, 8, 8)] {
            b.set(i, j, k, (i * 3 + j * 5 + k) as f32 * 0.173);
        }
        let g: BrickGrid<f32> = b.finish();
        let bits = |h: &BrickGrid<f16>| {
            let (_, table, constants, data) = h.raw();
            (
                table.to_vec(),
                constants.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                data.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            )
        };
        let want =
            BrickGrid::<f16>::from_fn(g.dims(), |i, j, k| g.fetch(i as i32, j as i32, k as i32))
                .unwrap();
        assert_eq!(bits(&g.to_voxel::<f16>()), bits(&want));
        let want32 =
            BrickGrid::<f32>::from_fn(g.dims(), |i, j, k| g.fetch(i as i32, j as i32, k as i32))
                .unwrap();
        let got32 = g.to_voxel::<f32>();
        assert_eq!(got32.raw().1, want32.raw().1);
        assert_eq!(got32.raw().3.len(), want32.raw().3.len());
    }

    #[test]
    fn builder_fill_and_set_match_from_fn() {
        let mut b = BrickGridBuilder::new([30, 30, 30], 0.0).unwrap();
        b.fill([0, 0, 0], [15, 15, 15], 2.0);
        b.fill([3, 4, 5], [20, 21, 22], 1.0);
        b.set(7, 7, 7, 5.0);
        let g: BrickGrid<f16> = b.finish();
        let reference = |i: u32, j: u32, k: u32| {
            if (i, j, k) == (7, 7, 7) {
                5.0
            } else if (3..=20).contains(&i) && (4..=21).contains(&j) && (5..=22).contains(&k) {
                1.0
            } else if i <= 15 && j <= 15 && k <= 15 {
                2.0
            } else {
                0.0
            }
        };
        for k in 0..30 {
            for j in 0..30 {
                for i in 0..30 {
                    assert_eq!(g.fetch(i, j, k), reference(i as u32, j as u32, k as u32));
                }
            }
        }
    }

    /// A builder over a grid whose size is no multiple of 8 (partial edge
    /// bricks), with a constant slab, bricks written voxel by voxel and a
    /// dense corner; `blocks` 8³ blocks at the given corners.
    fn builder(blocks: &[[i64; 3]], adopt: bool) -> BrickGridBuilder {
        let mut b = BrickGridBuilder::new([29, 18, 21], 0.5).unwrap();
        b.fill([0, 0, 12], [28, 17, 20], -0.25);
        for (n, &lo) in blocks.iter().enumerate() {
            let v =
                |i: u32, j: u32, k: u32| (n as u32 * 512 + i + 8 * j + 64 * k) as f32 * 0.013 - 2.0;
            let mut values = Box::new([0.0f32; BRICK_VOXELS]);
            for k in 0..BRICK {
                for j in 0..BRICK {
                    for i in 0..BRICK {
                        values[local_index(i, j, k)] = v(i, j, k);
                        if !adopt {
                            b.set(
                                lo[0] + i as i64,
                                lo[1] + j as i64,
                                lo[2] + k as i64,
                                v(i, j, k),
                            );
                        }
                    }
                }
            }
            if adopt {
                b.adopt(lo, values);
            }
        }
        b.set(3, 17, 2, 7.0);
        b
    }

    fn bits<T: Voxel>(g: &BrickGrid<T>) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let (_, table, constants, data) = g.raw();
        (
            table.to_vec(),
            constants.iter().map(|v| v.to_bits()).collect(),
            data.iter().map(|v| v.load().to_bits()).collect(),
        )
    }

    /// Blocks inside (adopted), across the high edges, unaligned and partly
    /// below zero (written voxel by voxel): as 512 `set` calls each.
    #[test]
    fn adopt_equals_setting_every_voxel() {
        let blocks = [
            [0, 0, 0],
            [8, 8, 8],
            [24, 0, 16],
            [16, 16, 0],
            [3, 5, 7],
            [-4, 0, 8],
        ];
        let (a, s) = (builder(&blocks, true), builder(&blocks, false));
        assert_eq!(bits(&a.finish::<f32>()), bits(&s.finish::<f32>()));
    }

    /// One pass equals finish → map_values → to_voxel, for half and single
    /// floats, with maps that turn data bricks constant (a clamp) or not.
    #[test]
    fn finish_converted_equals_finish_map_and_convert() {
        let blocks = [[0, 0, 0], [8, 8, 8], [24, 0, 16], [16, 16, 0], [3, 5, 7]];
        let fog = |v: f32| (-v / 0.5f32).clamp(0.0, 1.0);
        let clamp = |v: f32| v.max(0.0);
        let square = |v: f32| v * v + 0.1;
        for f in [&fog as &(dyn Fn(f32) -> f32 + Sync), &clamp, &square] {
            let want = builder(&blocks, true).finish::<f32>().map_values(f);
            let got16 = builder(&blocks, true).finish_converted::<f16>(f);
            assert_eq!(bits(&got16), bits(&want.to_voxel::<f16>()));
            let got32 = builder(&blocks, true).finish_converted::<f32>(f);
            assert_eq!(bits(&got32), bits(&want.to_voxel::<f32>()));
        }
    }
}

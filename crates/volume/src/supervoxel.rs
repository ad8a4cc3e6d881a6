//! Super-voxel statistics: the low-resolution grid every estimator traverses.
//!
//! Each super-voxel covers `r³` voxels (default 16, Peters 2025 §4.2) and stores,
//! in extinction units, the minimum (control variate / minorant), maximum
//! (majorant), mean (Kettunen et al. 2021 importance) and the variance-aware
//! importance of Peters 2025 Eq. 5. With trilinear or stochastic filtering a
//! point in the super-voxel reads voxels one step outside it, so the
//! statistics cover a one-voxel apron and the bounds stay conservative.
//! Stored in f32, so bounds computed from the (possibly f16) voxel values are
//! exact for the stored field.

use fogbank_math::PiecewiseLinear;
use rayon::prelude::*;

/// `uniform` for fields without a cheap uniformity test.
fn no_uniform(_: [i32; 3], _: [i32; 3]) -> Option<f32> {
    None
}

/// Statistics of a classified cell σ_t = α(s) (see `build_classified`).
fn classified(
    values: impl Iterator<Item = f32> + Clone,
    opacity: &PiecewiseLinear<1>,
) -> SuperVoxel {
    let (lo, hi) = values
        .clone()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    let mut sv = SuperVoxel::from_values(values.map(|v| opacity.eval(v)[0]));
    let (min, max) = opacity.range_over(lo, hi);
    sv.min = sv.min.min(min);
    sv.max = sv.max.max(max);
    sv
}

/// One super-voxel, laid out as a `vec4<f32>` for the GPU.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SuperVoxel {
    pub min: f32,
    pub max: f32,
    pub mean: f32,
    /// Peters 2025, Eq. 5: P = sqrt(1/R Σ (μ_j − μ_min)²).
    pub importance: f32,
}

impl SuperVoxel {
    /// Statistics of a set of extinction values (Eq. 5 for `importance`).
    pub fn from_values(values: impl Iterator<Item = f32> + Clone) -> Self {
        let (mut min, mut max, mut sum, mut n) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f64, 0u64);
        for v in values.clone() {
            min = min.min(v);
            max = max.max(v);
            sum += v as f64;
            n += 1;
        }
        if n == 0 {
            return SuperVoxel::default();
        }
        let sq: f64 = values.map(|v| ((v - min) as f64).powi(2)).sum();
        // A homogeneous but non-empty super-voxel keeps a small importance, so
        // the importance is zero exactly where the extinction is (notes:
        // clamped to ≥ 0.01 μ_min, as in the author's code).
        let importance = ((sq / n as f64).sqrt() as f32).max(0.01 * min);
        SuperVoxel {
            min,
            max,
            mean: (sum / n as f64) as f32,
            importance,
        }
    }

    pub fn scaled(self, s: f32) -> Self {
        SuperVoxel {
            min: self.min * s,
            max: self.max * s,
            mean: self.mean * s,
            importance: self.importance * s,
        }
    }
}

/// The voxel values of one cell and its apron, x fastest.
pub struct CellValues<'a, F> {
    fetch: &'a F,
    lo: [i32; 3],
    hi: [i32; 3],
    /// The next voxel to read; `next[2] > hi[2]` when done.
    next: [i32; 3],
}

impl<F> Clone for CellValues<'_, F> {
    fn clone(&self) -> Self {
        CellValues { ..*self }
    }
}

impl<F: Fn(i32, i32, i32) -> f32> Iterator for CellValues<'_, F> {
    type Item = f32;
    fn next(&mut self) -> Option<f32> {
        let [i, j, k] = self.next;
        if k > self.hi[2] || self.lo[0] > self.hi[0] || self.lo[1] > self.hi[1] {
            return None;
        }
        self.next = if i < self.hi[0] {
            [i + 1, j, k]
        } else if j < self.hi[1] {
            [self.lo[0], j + 1, k]
        } else {
            [self.lo[0], self.lo[1], k + 1]
        };
        Some((self.fetch)(i, j, k))
    }
}

#[derive(Clone, Debug)]
pub struct SuperVoxelGrid {
    /// Edge length `r` in voxels.
    pub size: u32,
    pub dims: [u32; 3],
    pub cells: Vec<SuperVoxel>,
    /// Per cell: [`ZERO_NEAREST`] | [`ZERO_TRILINEAR`] where the field is
    /// exactly zero (what empty-space skipping may jump over).
    zero: Vec<u8>,
}

/// The cell's own voxels are all zero: the nearest-filtered field is zero
/// in its region.
pub const ZERO_NEAREST: u8 = 1;
/// Every voxel a trilinear lookup in the cell's region reads (the cell and
/// a one-voxel apron) is zero.
pub const ZERO_TRILINEAR: u8 = 2;

impl SuperVoxelGrid {
    /// Builds the statistics of a voxel grid of `dims` voxels read through
    /// `fetch` (clamped indices), with an apron of `apron` voxels.
    pub fn build(
        dims: [u32; 3],
        size: u32,
        apron: u32,
        fetch: impl Fn(i32, i32, i32) -> f32 + Sync,
    ) -> Self {
        Self::build_with(dims, size, apron, fetch, no_uniform, |v| {
            SuperVoxel::from_values(v)
        })
    }

    /// [`Self::build`] (`opacity` None) or [`Self::build_classified`] of a
    /// sparse field: `uniform(lo, hi)` returns the value of every voxel in
    /// the inclusive index box `[lo, hi]` (clamped reads) when they are all
    /// equal, and such cells read one voxel instead of all of them. The
    /// statistics are the same bit for bit: n equal values c have minimum,
    /// maximum and mean c (their f64 sum n·c is exact while n < 2²⁹) and a
    /// zero spread, whatever n is. For grids of constant bricks (sparse VDB
    /// files, whose empty space is one constant) this skips the voxels of
    /// every empty super-voxel.
    pub fn build_sparse(
        dims: [u32; 3],
        size: u32,
        apron: u32,
        fetch: impl Fn(i32, i32, i32) -> f32 + Sync,
        uniform: impl Fn([i32; 3], [i32; 3]) -> Option<f32> + Sync,
        opacity: Option<&PiecewiseLinear<1>>,
    ) -> Self {
        match opacity {
            None => Self::build_with(dims, size, apron, fetch, uniform, |v| {
                SuperVoxel::from_values(v)
            }),
            Some(tf) => Self::build_with(dims, size, apron, fetch, uniform, |v| classified(v, tf)),
        }
    }

    /// The statistics of a classified field σ_t = α(s) of the voxel values
    /// `s` (post-interpolative: a lookup interpolates s, then applies α).
    /// Interpolated values lie in the cell's [min s, max s], so the bounds
    /// are α's extrema over that range (not over the voxel values, which
    /// would miss a peak of α between them); mean and importance come from
    /// the classified voxels.
    pub fn build_classified(
        dims: [u32; 3],
        size: u32,
        apron: u32,
        fetch: impl Fn(i32, i32, i32) -> f32 + Sync,
        opacity: &PiecewiseLinear<1>,
    ) -> Self {
        Self::build_with(dims, size, apron, fetch, no_uniform, |values| {
            classified(values, opacity)
        })
    }

    /// [`Self::build`] with the statistics of each cell's values (its own
    /// voxels and the apron) computed by `stats`.
    fn build_with<F, U, S>(
        dims: [u32; 3],
        size: u32,
        apron: u32,
        fetch: F,
        uniform: U,
        stats: S,
    ) -> Self
    where
        F: Fn(i32, i32, i32) -> f32 + Sync,
        U: Fn([i32; 3], [i32; 3]) -> Option<f32> + Sync,
        S: Fn(CellValues<'_, F>) -> SuperVoxel + Sync,
    {
        let size = size.max(1);
        let sdims = dims.map(|d| d.div_ceil(size));
        let n = sdims.iter().map(|&d| d as usize).product::<usize>();
        let cells = (0..n)
            .into_par_iter()
            .map(|c| {
                let cx = (c % sdims[0] as usize) as i32;
                let cy = ((c / sdims[0] as usize) % sdims[1] as usize) as i32;
                let cz = (c / (sdims[0] as usize * sdims[1] as usize)) as i32;
                let lo = [cx, cy, cz].map(|v| v * size as i32 - apron as i32);
                let hi: [i32; 3] = std::array::from_fn(|a| {
                    // Voxels past the grid read the clamped border value, which
                    // the clamp below already includes.
                    (([cx, cy, cz][a] + 1) * size as i32 + apron as i32 - 1)
                        .min(dims[a] as i32 - 1 + apron as i32)
                });
                let lo = lo.map(|v| v.max(-(apron as i32)));
                let count: i64 = (0..3).map(|a| (hi[a] - lo[a] + 1).max(0) as i64).product();
                // A uniform cell: its first voxel stands for all (same statistics).
                let hi = if count > 0 && count < 1 << 29 && uniform(lo, hi).is_some() {
                    lo
                } else {
                    hi
                };
                stats(CellValues {
                    fetch: &fetch,
                    lo,
                    hi,
                    next: lo,
                })
            })
            .collect();
        SuperVoxelGrid::new(size, sdims, cells, apron)
    }

    /// A grid of `cells` (x fastest) whose bounds cover an apron of `apron`
    /// voxels (≥ 1: they bound the trilinear field in the cell's region).
    pub fn new(size: u32, dims: [u32; 3], cells: Vec<SuperVoxel>, apron: u32) -> Self {
        let mut g = SuperVoxelGrid {
            size,
            dims,
            cells,
            zero: Vec::new(),
        };
        g.zero = g.zero_flags(apron);
        g
    }

    /// Without an apron the trilinear flag needs the 26 neighbours to be
    /// zero too (a trilinear lookup reads at most one voxel into them).
    fn zero_flags(&self, apron: u32) -> Vec<u8> {
        let own: Vec<bool> = self
            .cells
            .iter()
            .map(|c| c.min == 0.0 && c.max == 0.0)
            .collect();
        let d = self.dims.map(|v| v as i32);
        let index = |c: [i32; 3]| ((c[2] * d[1] + c[1]) * d[0] + c[0]) as usize;
        (0..own.len())
            .map(|i| {
                if !own[i] {
                    return 0;
                }
                let c = [
                    i as i32 % d[0],
                    (i as i32 / d[0]) % d[1],
                    i as i32 / (d[0] * d[1]),
                ];
                let tri = apron >= 1
                    || (0..27).all(|n| {
                        let o = [n % 3 - 1, (n / 3) % 3 - 1, n / 9 - 1];
                        own[index(std::array::from_fn(|a| (c[a] + o[a]).clamp(0, d[a] - 1)))]
                    });
                ZERO_NEAREST | if tri { ZERO_TRILINEAR } else { 0 }
            })
            .collect()
    }

    /// Whether the field read with `flag` ([`ZERO_NEAREST`] or
    /// [`ZERO_TRILINEAR`]) is zero everywhere in cell `c`.
    #[inline(always)]
    pub fn is_zero(&self, c: [i32; 3], flag: u8) -> bool {
        self.zero
            [((c[2] as u32 * self.dims[1] + c[1] as u32) * self.dims[0] + c[0] as u32) as usize]
            & flag
            != 0
    }

    #[inline(always)]
    pub fn get(&self, c: [i32; 3]) -> &SuperVoxel {
        &self.cells
            [((c[2] as u32 * self.dims[1] + c[1] as u32) * self.dims[0] + c[0] as u32) as usize]
    }

    pub fn scaled(&self, s: f32) -> Self {
        let cells: Vec<SuperVoxel> = self.cells.iter().map(|c| c.scaled(s)).collect();
        // A finite non-zero scale keeps zeros zero and non-zeros non-zero.
        let zero = if s.is_finite() && s != 0.0 {
            self.zero.clone()
        } else {
            let own = |c: &SuperVoxel| c.min == 0.0 && c.max == 0.0;
            cells
                .iter()
                .map(|c| {
                    if own(c) {
                        ZERO_NEAREST | ZERO_TRILINEAR
                    } else {
                        0
                    }
                })
                .collect()
        };
        SuperVoxelGrid {
            size: self.size,
            dims: self.dims,
            cells,
            zero,
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.cells.len() * std::mem::size_of::<SuperVoxel>()
    }
}

#[cfg(test)]
mod supervoxel_test {
    use super::*;

    #[test]
    fn importance_is_rms_above_minimum() {
        let s = SuperVoxel::from_values([1.0f32, 1.0, 3.0, 5.0].into_iter());
        assert_eq!((s.min, s.max, s.mean), (1.0, 5.0, 2.5));
        let expected = ((0.0 + 0.0 + 4.0 + 16.0) / 4.0f64).sqrt() as f32;
        assert!((s.importance - expected).abs() < 1e-6);
    }

    #[test]
    fn apron_makes_bounds_conservative() {
        // A spike just outside super-voxel (0,0,0) must raise its maximum.
        let fetch = |i: i32, j: i32, k: i32| if (i, j, k) == (4, 0, 0) { 9.0 } else { 1.0 };
        let no_apron = SuperVoxelGrid::build([8, 4, 4], 4, 0, fetch);
        let apron = SuperVoxelGrid::build([8, 4, 4], 4, 1, fetch);
        assert_eq!(no_apron.get([0, 0, 0]).max, 1.0);
        assert_eq!(apron.get([0, 0, 0]).max, 9.0);
        assert_eq!(apron.get([1, 0, 0]).max, 9.0);
    }

    #[test]
    fn sparse_build_equals_the_full_build_bit_for_bit() {
        use crate::grid::BrickGrid;
        // Empty space (0), a constant slab (0.37) and dense bricks, over
        // partial bricks at the far faces.
        let g = BrickGrid::<f32>::from_fn([45, 37, 29], |i, j, k| {
            if k >= 24 {
                0.37
            } else if (8..24).contains(&i) && (8..16).contains(&j) {
                ((i * 31 + j * 17 + k * 7) % 23) as f32 * 0.061 + 0.013
            } else {
                0.0
            }
        })
        .unwrap();
        assert_eq!(g.uniform_in([0, 0, 0], [7, 7, 7]), Some(0.0));
        assert_eq!(g.uniform_in([-1, -1, 25], [50, 50, 40]), Some(0.37));
        assert_eq!(g.uniform_in([0, 0, 0], [7, 7, 24]), None);
        assert_eq!(g.uniform_in([8, 8, 0], [9, 9, 1]), None);
        let tf = PiecewiseLinear::new(vec![(0.0, [0.2]), (0.3, [0.9]), (1.0, [0.1])]).unwrap();
        let fetch = |i, j, k| g.fetch(i, j, k);
        for size in [1, 4, 8, 16] {
            for apron in [0, 1] {
                let full = SuperVoxelGrid::build(g.dims(), size, apron, fetch);
                let full_tf = SuperVoxelGrid::build_classified(g.dims(), size, apron, fetch, &tf);
                let uniform = |lo, hi| g.uniform_in(lo, hi);
                let sparse =
                    SuperVoxelGrid::build_sparse(g.dims(), size, apron, fetch, uniform, None);
                let sparse_tf =
                    SuperVoxelGrid::build_sparse(g.dims(), size, apron, fetch, uniform, Some(&tf));
                let bits = |c: &[SuperVoxel]| {
                    c.iter()
                        .flat_map(|s| [s.min, s.max, s.mean, s.importance].map(f32::to_bits))
                        .collect::<Vec<_>>()
                };
                assert_eq!(
                    bits(&full.cells),
                    bits(&sparse.cells),
                    "size {size} apron {apron}"
                );
                assert_eq!(
                    bits(&full_tf.cells),
                    bits(&sparse_tf.cells),
                    "size {size} apron {apron}"
                );
                assert_eq!(full.zero, sparse.zero);
            }
        }
    }
}

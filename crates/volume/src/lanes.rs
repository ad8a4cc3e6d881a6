//! Filtered lookups eight at a time: the σ_t of eight points evaluated in
//! SIMD lanes (AVX2 + F16C, detected at run time), bit for bit the scalar
//! lookups of `access.rs`.
//!
//! Fixed-count estimators (the jackknife's 2N lookups, ray
//! marching, Kettunen et al.'s estimators) know all their sample points
//! before they read the volume, so they can read them together. One lane per
//! point: the floor, the per-axis clamping (so points whose 2×2×2 block
//! crosses a brick or grid border cost the same as any other — a third of
//! the points of a grid of 8³ bricks take the scalar general path), the
//! brick-table gather, the voxel gather (half floats converted by F16C) and
//! the blend. The blend keeps the scalar expression's order of operations
//! without fused multiply-adds, so every lane rounds as the scalar code does.
//! Where AVX2 or F16C is missing, or a grid is too large for 32-bit gather
//! indices, every point takes the scalar lookup.

use crate::access::Filter;
use crate::grid::{BrickGrid, Voxel};
use fogbank_math::Vec3;

/// Points per SIMD batch.
pub const LANES: usize = 8;

impl<T: Voxel> BrickGrid<T> {
    /// Whether `filtered_lanes` evaluates this grid in SIMD lanes on this
    /// CPU (otherwise it loops over the scalar lookup).
    pub fn lanes_in_simd(&self) -> bool {
        #[cfg(target_arch = "x86_64")]
        return simd::usable(self);
        #[allow(unreachable_code)]
        false
    }

    /// `out[l] = self.filtered(filter, p[l], u[l])` for every `l`, bit for
    /// bit; `u` is read only by `StochasticTrilinear` (it may be empty for
    /// the other filters).
    pub fn filtered_lanes(&self, filter: Filter, p: &[Vec3], u: &[Vec3], out: &mut [f32]) {
        let n = p.len().min(out.len());
        let jitter = filter == Filter::StochasticTrilinear;
        let u_at = |l: usize| if jitter { u[l] } else { Vec3::ZERO };
        let mut done = 0;
        #[cfg(target_arch = "x86_64")]
        if simd::usable(self) {
            while done + LANES <= n {
                let (ps, us) = (
                    &p[done..done + LANES],
                    std::array::from_fn(|l| u_at(done + l)),
                );
                let ps: [Vec3; LANES] = std::array::from_fn(|l| ps[l]);
                // SAFETY: `usable` checked the CPU features and the index
                // ranges the gathers rely on.
                let v = unsafe { simd::filtered8(self, filter, &ps, &us) };
                out[done..done + LANES].copy_from_slice(&v);
                done += LANES;
            }
            // A partial batch of more than two points: pad with the last one.
            if n - done > 2 {
                let ps: [Vec3; LANES] = std::array::from_fn(|l| p[(done + l).min(n - 1)]);
                let us = std::array::from_fn(|l| u_at((done + l).min(n - 1)));
                // SAFETY: as above.
                let v = unsafe { simd::filtered8(self, filter, &ps, &us) };
                out[done..n].copy_from_slice(&v[..n - done]);
                done = n;
            }
        }
        for l in done..n {
            out[l] = self.filtered(filter, p[l], u_at(l));
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod simd {
    use super::LANES;
    use crate::access::Filter;
    use crate::grid::{BrickGrid, Voxel, BRICK_LOG2};
    use fogbank_math::Vec3;
    use std::arch::x86_64::*;

    /// Whether the SIMD path may run for `g`: the CPU has AVX2 and F16C
    /// (`is_x86_feature_detected!` caches its answer), the voxel type is one
    /// the lanes read, and every table, data and constant index fits a
    /// signed 32-bit gather index (the scaled byte offset included). Half
    /// floats are read as 32-bit words that start one voxel early, so the
    /// data needs at least two voxels.
    pub fn usable<T: Voxel>(g: &BrickGrid<T>) -> bool {
        let (_, table, constants, data) = g.raw();
        let small = |n: usize| n < (1 << 29);
        let kind = match T::LANE_BITS {
            32 => true,
            16 => data.len() >= 2 || data.is_empty(),
            _ => false,
        };
        kind && small(table.len())
            && small(constants.len())
            && small(data.len())
            && is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("f16c")
    }

    /// The filtered value of eight points: `BrickGrid::filtered`, lane by lane.
    ///
    /// # Safety
    /// The CPU supports AVX2 and F16C and `usable(g)` holds.
    #[target_feature(enable = "avx2,f16c")]
    pub unsafe fn filtered8<T: Voxel>(
        g: &BrickGrid<T>,
        filter: Filter,
        p: &[Vec3; LANES],
        u: &[Vec3; LANES],
    ) -> [f32; LANES] {
        let axis = |f: fn(&Vec3) -> f32, v: &[Vec3; LANES]| {
            _mm256_setr_ps(
                f(&v[0]),
                f(&v[1]),
                f(&v[2]),
                f(&v[3]),
                f(&v[4]),
                f(&v[5]),
                f(&v[6]),
                f(&v[7]),
            )
        };
        let (x, y, z) = (axis(|v| v.x, p), axis(|v| v.y, p), axis(|v| v.z, p));
        let half = _mm256_set1_ps(0.5);
        let dims = g.dims();
        let r = match filter {
            Filter::Nearest => nearest(g, [x, y, z], dims),
            Filter::StochasticTrilinear => {
                // (p + u) − ½, in the scalar code's order.
                let (ux, uy, uz) = (axis(|v| v.x, u), axis(|v| v.y, u), axis(|v| v.z, u));
                let q = [
                    _mm256_sub_ps(_mm256_add_ps(x, ux), half),
                    _mm256_sub_ps(_mm256_add_ps(y, uy), half),
                    _mm256_sub_ps(_mm256_add_ps(z, uz), half),
                ];
                nearest(g, q, dims)
            }
            Filter::Trilinear => trilinear(
                g,
                [
                    _mm256_sub_ps(x, half),
                    _mm256_sub_ps(y, half),
                    _mm256_sub_ps(z, half),
                ],
                dims,
            ),
        };
        let mut out = [0.0f32; LANES];
        _mm256_storeu_ps(out.as_mut_ptr(), r);
        out
    }

    /// `floor(x) as i32` as the scalar code computes it (`floor_i32`,
    /// `floor_f32(x) as i32`: saturating), for a floored `f`. Values at or
    /// above 2³⁰ are capped first (`cvttps` would give i32::MIN where `as`
    /// saturates high; every such index clamps to the last voxel either way);
    /// NaN passes the cap (`min_ps` returns its second operand for NaN) and
    /// converts to i32::MIN, which clamps to 0 as `NaN as i32 = 0` does.
    #[inline(always)]
    unsafe fn to_index(f: __m256) -> __m256i {
        _mm256_cvttps_epi32(_mm256_min_ps(_mm256_set1_ps(1_073_741_824.0), f))
    }

    #[inline(always)]
    unsafe fn clamp(i: __m256i, last: i32) -> __m256i {
        _mm256_min_epi32(
            _mm256_max_epi32(i, _mm256_setzero_si256()),
            _mm256_set1_epi32(last),
        )
    }

    /// `BrickGrid::nearest` (a clamped `fetch` at the floor of `q`).
    #[inline(always)]
    unsafe fn nearest<T: Voxel>(g: &BrickGrid<T>, q: [__m256; 3], dims: [u32; 3]) -> __m256 {
        let idx = |a: usize| {
            let f = _mm256_floor_ps(q[a]);
            clamp(to_index(f), dims[a] as i32 - 1)
        };
        fetch8(g, idx(0), idx(1), idx(2))
    }

    /// `BrickGrid::trilinear_clamped` for `q = p − ½` (equal, bit for bit, to
    /// the brick fast path of `trilinear` wherever that applies).
    #[inline(always)]
    unsafe fn trilinear<T: Voxel>(g: &BrickGrid<T>, q: [__m256; 3], dims: [u32; 3]) -> __m256 {
        let one = _mm256_set1_epi32(1);
        let mut lo = [_mm256_setzero_si256(); 3];
        let mut hi = [_mm256_setzero_si256(); 3];
        let mut w = [_mm256_setzero_ps(); 3];
        for a in 0..3 {
            let f = _mm256_floor_ps(q[a]);
            w[a] = _mm256_sub_ps(q[a], f);
            let i = to_index(f);
            let last = dims[a] as i32 - 1;
            lo[a] = clamp(i, last);
            hi[a] = clamp(_mm256_add_epi32(i, one), last);
        }
        let c = [
            fetch8(g, lo[0], lo[1], lo[2]),
            fetch8(g, hi[0], lo[1], lo[2]),
            fetch8(g, lo[0], hi[1], lo[2]),
            fetch8(g, hi[0], hi[1], lo[2]),
            fetch8(g, lo[0], lo[1], hi[2]),
            fetch8(g, hi[0], lo[1], hi[2]),
            fetch8(g, lo[0], hi[1], hi[2]),
            fetch8(g, hi[0], hi[1], hi[2]),
        ];
        blend(c, w)
    }

    /// `access::blend` in lanes: the same operations in the same order.
    #[inline(always)]
    unsafe fn blend(c: [__m256; 8], w: [__m256; 3]) -> __m256 {
        let lerp = |a: __m256, b: __m256, t: __m256| {
            _mm256_add_ps(a, _mm256_mul_ps(t, _mm256_sub_ps(b, a)))
        };
        let c00 = lerp(c[0], c[1], w[0]);
        let c10 = lerp(c[2], c[3], w[0]);
        let c01 = lerp(c[4], c[5], w[0]);
        let c11 = lerp(c[6], c[7], w[0]);
        let c0 = lerp(c00, c10, w[1]);
        let c1 = lerp(c01, c11, w[1]);
        lerp(c0, c1, w[2])
    }

    /// `BrickGrid::fetch_in_grid` for eight in-grid voxels: one gather of
    /// table entries, one of voxels (lanes in data bricks) and, when any
    /// lane lies in a constant brick, one of constants.
    #[inline(always)]
    unsafe fn fetch8<T: Voxel>(g: &BrickGrid<T>, i: __m256i, j: __m256i, k: __m256i) -> __m256 {
        let (bdims, table, constants, data) = g.raw();
        let m = _mm256_set1_epi32((1 << BRICK_LOG2) - 1);
        let brick = |v: __m256i| _mm256_srli_epi32::<{ BRICK_LOG2 as i32 }>(v);
        let b = _mm256_add_epi32(
            _mm256_mullo_epi32(
                _mm256_add_epi32(
                    _mm256_mullo_epi32(brick(k), _mm256_set1_epi32(bdims[1] as i32)),
                    brick(j),
                ),
                _mm256_set1_epi32(bdims[0] as i32),
            ),
            brick(i),
        );
        let entry = _mm256_i32gather_epi32::<4>(table.as_ptr() as *const i32, b);
        // Entries with the top bit (`CONSTANT`) set index `constants`.
        let constant = _mm256_srai_epi32::<31>(entry);
        let in_data = _mm256_xor_si256(constant, _mm256_set1_epi32(-1));
        let local = _mm256_or_si256(
            _mm256_or_si256(
                _mm256_slli_epi32::<{ 2 * BRICK_LOG2 as i32 }>(_mm256_and_si256(k, m)),
                _mm256_slli_epi32::<{ BRICK_LOG2 as i32 }>(_mm256_and_si256(j, m)),
            ),
            _mm256_and_si256(i, m),
        );
        let index = _mm256_add_epi32(_mm256_slli_epi32::<{ 3 * BRICK_LOG2 as i32 }>(entry), local);
        let mut value = _mm256_setzero_ps();
        if _mm256_movemask_ps(_mm256_castsi256_ps(in_data)) != 0 {
            value = match T::LANE_BITS {
                32 => _mm256_mask_i32gather_ps::<4>(
                    value,
                    data.as_ptr() as *const f32,
                    index,
                    _mm256_castsi256_ps(in_data),
                ),
                _ => half_gather(data.as_ptr() as *const i32, index, in_data),
            };
        }
        if _mm256_movemask_ps(_mm256_castsi256_ps(constant)) != 0 {
            let slot = _mm256_and_si256(entry, _mm256_set1_epi32(i32::MAX));
            let c = _mm256_mask_i32gather_ps::<4>(
                _mm256_setzero_ps(),
                constants.as_ptr(),
                slot,
                _mm256_castsi256_ps(constant),
            );
            value = _mm256_blendv_ps(value, c, _mm256_castsi256_ps(constant));
        }
        value
    }

    /// Half-float voxels `index` of `data` (lanes in `mask`), as f32. Each
    /// lane reads the 32-bit word that ends with its voxel (starting one
    /// voxel early, or at voxel 0 for index 0), so no read passes the end of
    /// the data.
    #[inline(always)]
    unsafe fn half_gather(data: *const i32, index: __m256i, mask: __m256i) -> __m256 {
        let zero = _mm256_setzero_si256();
        let positive = _mm256_cmpgt_epi32(index, zero);
        let start = _mm256_add_epi32(index, positive); // index − 1 where index > 0
        let word = _mm256_mask_i32gather_epi32::<2>(zero, data, start, mask);
        let shift = _mm256_and_si256(positive, _mm256_set1_epi32(16));
        let bits = _mm256_and_si256(_mm256_srlv_epi32(word, shift), _mm256_set1_epi32(0xffff));
        // Eight 16-bit values in order in the low 128 bits.
        let packed = _mm256_permute4x64_epi64::<0b00_00_10_00>(_mm256_packus_epi32(bits, bits));
        _mm256_cvtph_ps(_mm256_castsi256_si128(packed))
    }
}

#[cfg(test)]
mod lanes_test {
    use super::*;
    use crate::grid::BrickGrid;
    use fogbank_math::Pcg32;
    use half::f16;

    /// A grid of whole and partial bricks, some constant, values with many
    /// mantissa bits.
    fn grid<T: Voxel>(dims: [u32; 3]) -> BrickGrid<T> {
        BrickGrid::<T>::from_fn(dims, |i, j, k| {
            if (i / 8 + j / 8 + k / 8) % 3 == 0 {
                0.75
            } else {
                ((i * 7919 + j * 104_729 + k * 1_299_709) % 1000) as f32 * 0.013_7 + 0.1
            }
        })
        .unwrap()
    }

    fn points(dims: [u32; 3], n: usize, rng: &mut Pcg32) -> Vec<Vec3> {
        let mut p: Vec<Vec3> = (0..n)
            .map(|_| {
                // Inside [−1, dims + 1] with extra weight on voxel and brick borders.
                let c = |d: u32, rng: &mut Pcg32| match rng.next_u32() % 4 {
                    0 => (rng.next_u32() % (d + 1)) as f32,
                    1 => (rng.next_u32() % (d / 8 + 1)) as f32 * 8.0 + 0.5,
                    _ => rng.next_f32() * (d as f32 + 2.0) - 1.0,
                };
                Vec3::new(c(dims[0], rng), c(dims[1], rng), c(dims[2], rng))
            })
            .collect();
        p.extend([
            Vec3::ZERO,
            Vec3::splat(-0.0),
            Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32),
        ]);
        p
    }

    fn check<T: Voxel>(dims: [u32; 3]) {
        let g = grid::<T>(dims);
        // The comparison below must be between two implementations.
        #[cfg(target_arch = "x86_64")]
        if is_x86_feature_detected!("avx2") && is_x86_feature_detected!("f16c") {
            assert!(g.lanes_in_simd());
        }
        let mut rng = Pcg32::new(17, dims[0] as u64);
        let p = points(dims, 4000, &mut rng);
        let u: Vec<Vec3> = p
            .iter()
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
            .collect();
        for filter in [
            Filter::Nearest,
            Filter::Trilinear,
            Filter::StochasticTrilinear,
        ] {
            // Every batch length, so padded partial batches are covered.
            for len in [1, 3, 7, 8, 13, 16, 64] {
                for start in (0..p.len() - len).step_by(len * 3 + 1) {
                    let (ps, us) = (&p[start..start + len], &u[start..start + len]);
                    let mut out = vec![f32::NAN; len];
                    g.filtered_lanes(filter, ps, us, &mut out);
                    for l in 0..len {
                        let want = g.filtered(filter, ps[l], us[l]);
                        assert_eq!(
                            out[l].to_bits(),
                            want.to_bits(),
                            "{} {filter:?} p = {:?}: {} vs {}",
                            T::NAME,
                            ps[l],
                            out[l],
                            want
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn lanes_equal_scalar_lookups_bit_for_bit() {
        for dims in [[24, 16, 8], [19, 13, 11], [1, 9, 2], [3, 3, 3]] {
            check::<f32>(dims);
            check::<f16>(dims);
        }
    }

    #[test]
    fn lanes_handle_all_constant_grids() {
        let g = BrickGrid::<f16>::from_fn([16, 16, 16], |_, _, _| 2.5).unwrap();
        let p = [Vec3::new(3.3, 8.0, 15.9); 9];
        let mut out = [0.0; 9];
        g.filtered_lanes(Filter::Trilinear, &p, &[], &mut out);
        assert!(out.iter().all(|&v| v == 2.5));
    }
}

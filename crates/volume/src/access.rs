//! The narrow volume-access interface every estimator is written against.
//!
//! Estimators are generic over [`VolumeAccess`], so the hot loop is
//! monomorphised per storage type with no dynamic dispatch, and the WGSL port
//! implements the same three operations: a filtered extinction lookup, the
//! super-voxel statistics, and the index-space box.

use crate::grid::{BrickGrid, Voxel};
use crate::supervoxel::SuperVoxelGrid;
use fogbank_math::{PiecewiseLinear, Vec3};

/// Reconstruction filter of a voxel grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    /// Value of the voxel containing the point (piecewise constant).
    Nearest,
    /// Trilinear interpolation between voxel centres.
    Trilinear,
    /// Nearest lookup after a uniform jitter in [−½, ½)³ of the continuous
    /// position; its expectation is the trilinear interpolant (Peters 2025 §6).
    #[default]
    StochasticTrilinear,
}

impl Filter {
    pub fn name(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Trilinear => "trilinear",
            Filter::StochasticTrilinear => "stochastic_trilinear",
        }
    }

    pub fn parse(s: &str) -> Option<Filter> {
        match s {
            "nearest" => Some(Filter::Nearest),
            "trilinear" => Some(Filter::Trilinear),
            "stochastic_trilinear" => Some(Filter::StochasticTrilinear),
            _ => None,
        }
    }

    /// Voxels a filtered lookup inside a cell may read beyond the cell.
    pub fn apron(self) -> u32 {
        match self {
            Filter::Nearest => 0,
            _ => 1,
        }
    }
}

pub trait VolumeAccess: Sync {
    /// Extinction σ_t at index-space point `p` (inside `[0, dims]`). `u` is a
    /// uniform point in [0, 1)³, used only by stochastic filtering.
    fn sigma_t(&self, p: Vec3, u: Vec3) -> f32;
    /// `out[l] = self.sigma_t(p[l], u[l])` for every `l < p.len()`, bit for
    /// bit (`u` may be empty when `needs_jitter` is false). Voxel grids
    /// evaluate eight points at a time in SIMD lanes (`lanes.rs`); other
    /// media take this loop.
    #[inline]
    fn sigma_t_lanes(&self, p: &[Vec3], u: &[Vec3], out: &mut [f32]) {
        for (l, o) in out.iter_mut().enumerate().take(p.len()) {
            *o = self.sigma_t(p[l], u.get(l).copied().unwrap_or(Vec3::ZERO));
        }
    }
    /// Whether `sigma_t` reads `u` (callers skip drawing it otherwise).
    fn needs_jitter(&self) -> bool;
    /// Super-voxel statistics in extinction units.
    fn supervoxels(&self) -> &SuperVoxelGrid;
    /// Index-space extent: the medium occupies `[0, dims]`.
    fn dims(&self) -> [u32; 3];
}

/// A voxel grid seen through a filter, an optional classification and an
/// extinction scale.
pub struct GridView<'a, T> {
    pub grid: &'a BrickGrid<T>,
    pub filter: Filter,
    pub scale: f32,
    pub supervoxels: &'a SuperVoxelGrid,
    /// Post-interpolative transfer function: σ_t = scale · α(filtered s).
    pub opacity: Option<&'a PiecewiseLinear<1>>,
}

/// Trilinear blend of the corner values `c` (order 000, 100, 010, 110, 001,
/// 101, 011, 111) with weights `w`: x first, then y, then z. Every trilinear
/// path goes through this one expression so that they agree bit for bit.
#[inline(always)]
fn blend(c: [f32; 8], w: Vec3) -> f32 {
    let c00 = c[0] + w.x * (c[1] - c[0]);
    let c10 = c[2] + w.x * (c[3] - c[2]);
    let c01 = c[4] + w.x * (c[5] - c[4]);
    let c11 = c[6] + w.x * (c[7] - c[6]);
    let c0 = c00 + w.y * (c10 - c00);
    let c1 = c01 + w.y * (c11 - c01);
    c0 + w.z * (c1 - c0)
}

/// `x.floor() as i32`, without the `floorf` call (the baseline x86-64 target
/// has no rounding instruction) in the common case x ≥ 0, where truncation is
/// the floor. NaN and negative values take `floor`; the result is the same
/// for every input (`as` saturates identically).
#[inline(always)]
pub fn floor_i32(x: f32) -> i32 {
    if x >= 0.0 {
        x as i32
    } else {
        x.floor() as i32
    }
}

/// `x.floor()`, bit for bit, without the `floorf` call for 0 < x < 2²³
/// (truncation is exact there and the result is an exact `i32`). Zeros keep
/// their sign through `floor`.
#[inline(always)]
pub fn floor_f32(x: f32) -> f32 {
    if x > 0.0 && x < 8_388_608.0 {
        x as i32 as f32
    } else {
        x.floor()
    }
}

impl<T: Voxel> BrickGrid<T> {
    #[inline(always)]
    pub fn nearest(&self, p: Vec3) -> f32 {
        self.fetch(floor_i32(p.x), floor_i32(p.y), floor_i32(p.z))
    }

    /// Trilinear interpolation between voxel centres, clamped at the border.
    ///
    /// Fast path (all eight corners in one brick and inside the grid, 67 % of
    /// the points of a grid of whole bricks): one table lookup and no
    /// clamping. Otherwise each axis is clamped once and the eight voxels are
    /// fetched individually. Both give exactly the value of the textbook
    /// form (eight clamped `fetch`es, `blend`), tested bit for bit.
    #[inline(always)]
    pub fn trilinear(&self, p: Vec3) -> f32 {
        let q = p - Vec3::splat(0.5);
        if q.x >= 0.0 && q.y >= 0.0 && q.z >= 0.0 {
            // q ≥ 0 (q = −0 is impossible: p − 0.5 rounds an exact zero to
            // +0): truncation is the floor, and for i < dims ≤ 2^16 the float
            // `i as f32` is exact, so w equals q − floor(q) bit for bit.
            let (i, j, k) = (q.x as i32 as u32, q.y as i32 as u32, q.z as i32 as u32);
            if let Some(c) = self.corners_in_brick(i, j, k) {
                let w = q - Vec3::new(i as f32, j as f32, k as f32);
                return blend(c, w);
            }
        }
        self.trilinear_clamped(q)
    }

    /// The general path of `trilinear` for `q = p − ½`: per-axis clamping.
    #[inline(never)]
    fn trilinear_clamped(&self, q: Vec3) -> f32 {
        let f = Vec3::new(floor_f32(q.x), floor_f32(q.y), floor_f32(q.z));
        let w = q - f;
        let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
        let [dx, dy, dz] = self.dims().map(|d| d as i32 - 1);
        let (i0, i1) = (i.clamp(0, dx) as u32, (i + 1).clamp(0, dx) as u32);
        let (j0, j1) = (j.clamp(0, dy) as u32, (j + 1).clamp(0, dy) as u32);
        let (k0, k1) = (k.clamp(0, dz) as u32, (k + 1).clamp(0, dz) as u32);
        let c = [
            self.fetch_in_grid(i0, j0, k0),
            self.fetch_in_grid(i1, j0, k0),
            self.fetch_in_grid(i0, j1, k0),
            self.fetch_in_grid(i1, j1, k0),
            self.fetch_in_grid(i0, j0, k1),
            self.fetch_in_grid(i1, j0, k1),
            self.fetch_in_grid(i0, j1, k1),
            self.fetch_in_grid(i1, j1, k1),
        ];
        blend(c, w)
    }

    /// The textbook form of `trilinear` (eight clamped `fetch`es), kept as
    /// the reference the fast paths are tested against.
    #[doc(hidden)]
    pub fn trilinear_reference(&self, p: Vec3) -> f32 {
        let q = p - Vec3::splat(0.5);
        let f = q.floor();
        let w = q - f;
        let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
        let c000 = self.fetch(i, j, k);
        let c100 = self.fetch(i + 1, j, k);
        let c010 = self.fetch(i, j + 1, k);
        let c110 = self.fetch(i + 1, j + 1, k);
        let c001 = self.fetch(i, j, k + 1);
        let c101 = self.fetch(i + 1, j, k + 1);
        let c011 = self.fetch(i, j + 1, k + 1);
        let c111 = self.fetch(i + 1, j + 1, k + 1);
        let c00 = c000 + w.x * (c100 - c000);
        let c10 = c010 + w.x * (c110 - c010);
        let c01 = c001 + w.x * (c101 - c001);
        let c11 = c011 + w.x * (c111 - c011);
        let c0 = c00 + w.y * (c10 - c00);
        let c1 = c01 + w.y * (c11 - c01);
        c0 + w.z * (c1 - c0)
    }

    /// The textbook form of `nearest`, for the same tests.
    #[doc(hidden)]
    pub fn nearest_reference(&self, p: Vec3) -> f32 {
        self.fetch(p.x.floor() as i32, p.y.floor() as i32, p.z.floor() as i32)
    }

    #[inline(always)]
    pub fn filtered(&self, filter: Filter, p: Vec3, u: Vec3) -> f32 {
        match filter {
            Filter::Nearest => self.nearest(p),
            Filter::Trilinear => self.trilinear(p),
            Filter::StochasticTrilinear => self.nearest(p + u - Vec3::splat(0.5)),
        }
    }
}

impl<T> GridView<'_, T> {
    /// The classified value α(s) of a stored value s (s itself without a
    /// transfer function); σ_t = `scale` · α(s). One predictable branch:
    /// media without a transfer function pay nothing else.
    #[inline(always)]
    pub fn classify(&self, s: f32) -> f32 {
        match self.opacity {
            None => s,
            Some(alpha) => alpha.eval(s)[0],
        }
    }
}

impl<T: Voxel> VolumeAccess for GridView<'_, T> {
    #[inline(always)]
    fn sigma_t(&self, p: Vec3, u: Vec3) -> f32 {
        self.scale * self.classify(self.grid.filtered(self.filter, p, u))
    }
    #[inline]
    fn sigma_t_lanes(&self, p: &[Vec3], u: &[Vec3], out: &mut [f32]) {
        self.grid.filtered_lanes(self.filter, p, u, out);
        for o in out.iter_mut().take(p.len()) {
            *o = self.scale * self.classify(*o);
        }
    }
    #[inline(always)]
    fn needs_jitter(&self) -> bool {
        self.filter == Filter::StochasticTrilinear
    }
    #[inline(always)]
    fn supervoxels(&self) -> &SuperVoxelGrid {
        self.supervoxels
    }
    #[inline(always)]
    fn dims(&self) -> [u32; 3] {
        self.grid.dims()
    }
}

#[cfg(test)]
mod access_test {
    use super::*;
    use fogbank_math::Pcg32;

    #[test]
    fn stochastic_trilinear_expectation_is_trilinear() {
        let g =
            BrickGrid::<f32>::from_fn([6, 5, 4], |i, j, k| ((i * 7 + j * 3 + k * 5) % 11) as f32)
                .unwrap();
        let mut rng = Pcg32::new(3, 9);
        for p in [
            Vec3::new(2.3, 1.7, 2.9),
            Vec3::new(0.2, 4.9, 0.6),
            Vec3::new(5.5, 2.5, 1.5),
        ] {
            let n = 200_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                let v = g.filtered(Filter::StochasticTrilinear, p, u) as f64;
                s += v;
                s2 += v * v;
            }
            let mean = s / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            let exact = g.trilinear(p) as f64;
            assert!(
                (mean - exact).abs() < 4.0 * se + 1e-9,
                "{p}: {mean} vs {exact} (se {se})"
            );
        }
    }

    /// Grids for the bit-for-bit tests: dense random values with some
    /// constant bricks (zero, −0, a constant), sizes that are and are not
    /// whole bricks, and degenerate one-voxel axes.
    fn test_grids<T: Voxel>() -> Vec<BrickGrid<T>> {
        let value = |i: u32, j: u32, k: u32| {
            let mut h = Pcg32::new((i as u64) | (j as u64) << 20 | (k as u64) << 40, 5);
            match (i >> 3, j >> 3, k >> 3) {
                (0, 0, 0) => 0.0,
                (1, 0, 0) => -0.0,
                (0, 1, 0) => 0.375,
                (0, 0, 1) => 1.0e30,
                _ => {
                    let v = h.next_f32() * 3.0 - 0.5;
                    match h.next_u32() % 16 {
                        0 => 0.0,
                        1 => -0.0,
                        2 => v * 1.0e-20,
                        _ => v,
                    }
                }
            }
        };
        [
            [21, 16, 13],
            [64, 64, 64],
            [8, 8, 8],
            [9, 17, 7],
            [1, 1, 1],
            [1, 9, 2],
        ]
        .into_iter()
        .map(|d| BrickGrid::<T>::from_fn(d, value).unwrap())
        .collect()
    }

    /// Random points in and around the grid, on voxel centres, on brick and
    /// grid borders, and one ULP either side of them.
    fn test_points(dims: [u32; 3], rng: &mut Pcg32, n: usize) -> Vec<Vec3> {
        let d = Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
        let special = |a: usize, rng: &mut Pcg32| -> f32 {
            let da = dims[a] as f32;
            let base = match rng.next_u32() % 8 {
                0 => 0.0,
                1 => da,
                2 => 0.5,
                3 => da - 0.5,
                // Brick borders in voxel-centre space: q = 8m − 1, 8m.
                4 => (8 * (rng.next_u32() % (dims[a] / 8 + 2))) as f32 - 0.5,
                5 => (8 * (rng.next_u32() % (dims[a] / 8 + 2))) as f32 + 0.5,
                6 => (rng.next_u32() % (dims[a] + 2)) as f32 + 0.5,
                _ => (rng.next_u32() % (dims[a] + 2)) as f32,
            };
            match rng.next_u32() % 3 {
                0 => base,
                1 => f32::from_bits(base.to_bits().wrapping_add(1)),
                _ => base - f32::EPSILON * base.abs().max(1.0),
            }
        };
        (0..n)
            .map(|t| {
                let r = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                let mut p = match t % 4 {
                    0 => r * d,
                    1 => r * (d + Vec3::splat(4.0)) - Vec3::splat(2.0),
                    _ => r * d,
                };
                if t % 4 >= 2 {
                    for a in 0..3 {
                        if rng.next_u32().is_multiple_of(2) {
                            p[a] = special(a, rng);
                        }
                    }
                }
                p
            })
            .collect()
    }

    fn check_bitwise<T: Voxel>() {
        let mut rng = Pcg32::new(17, 3);
        let (mut total, mut fast) = (0usize, 0usize);
        for g in test_grids::<T>() {
            for p in test_points(g.dims(), &mut rng, 100_000) {
                let same = |a: f32, b: f32| {
                    assert_eq!(
                        a.to_bits(),
                        b.to_bits(),
                        "{} {:?} at {p}: {a} vs {b}",
                        T::NAME,
                        g.dims()
                    )
                };
                same(g.trilinear(p), g.trilinear_reference(p));
                same(g.nearest(p), g.nearest_reference(p));
                let q = p - Vec3::splat(0.5);
                total += 1;
                if q.min_element() >= 0.0 {
                    let [i, j, k] = [q.x as u32, q.y as u32, q.z as u32];
                    fast += g.corners_in_brick(i, j, k).is_some() as usize;
                }
            }
            // NaN coordinates take the general path and agree too.
            for p in [
                Vec3::new(f32::NAN, 1.0, 1.0),
                Vec3::new(1.0, f32::NAN, 1.0),
                Vec3::new(1.0, 1.0, f32::NAN),
            ] {
                assert_eq!(g.trilinear(p).to_bits(), g.trilinear_reference(p).to_bits());
                assert_eq!(g.nearest(p).to_bits(), g.nearest_reference(p).to_bits());
            }
        }
        // Both paths are exercised.
        assert!(
            fast > total / 5 && fast < total * 4 / 5,
            "{fast} of {total}"
        );
    }

    #[test]
    fn fast_trilinear_and_nearest_are_bit_identical_to_the_reference_f32() {
        check_bitwise::<f32>();
    }

    #[test]
    fn fast_trilinear_and_nearest_are_bit_identical_to_the_reference_f16() {
        check_bitwise::<half::f16>();
    }

    #[test]
    fn floor_helpers_match_floor_bit_for_bit() {
        let mut xs = vec![
            0.0f32,
            -0.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x8000_0001),
            0.5,
            -0.5,
            1.0,
            -1.0,
            8_388_607.5,
            8_388_608.0,
            16_777_216.0,
            2_147_483_648.0,
            -2_147_483_648.0,
            3.0e38,
            -3.0e38,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        for b in [1.0f32, 7.0, 8.0, 63.0, 64.0, 8_388_608.0] {
            for x in [b, -b] {
                xs.extend([
                    f32::from_bits(x.to_bits() - 1),
                    x,
                    f32::from_bits(x.to_bits() + 1),
                ]);
            }
        }
        let mut rng = Pcg32::new(11, 2);
        xs.extend((0..200_000).map(|_| f32::from_bits(rng.next_u32())));
        xs.extend((0..200_000).map(|_| (rng.next_f32() - 0.25) * 100.0));
        for x in xs {
            assert_eq!(floor_f32(x).to_bits(), x.floor().to_bits(), "{x:e}");
            assert_eq!(floor_i32(x), x.floor() as i32, "{x:e}");
        }
    }

    #[test]
    fn trilinear_hits_voxel_centres() {
        let g =
            BrickGrid::<f32>::from_fn([4, 4, 4], |i, j, k| (i + 4 * j + 16 * k) as f32).unwrap();
        assert_eq!(g.trilinear(Vec3::new(1.5, 2.5, 3.5)), (1 + 8 + 48) as f32);
        assert_eq!(g.nearest(Vec3::new(1.99, 2.0, 3.5)), (1 + 8 + 48) as f32);
        // Clamped at the border: constant within half a voxel of the edge.
        assert_eq!(g.trilinear(Vec3::new(0.1, 0.5, 0.5)), 0.0);
    }
}

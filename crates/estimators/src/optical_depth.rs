//! Importance-sampled ray marching estimates of optical depth over the
//! super-voxel grid: Peters 2025 Alg. 2 (preparation) and Alg. 1 (interleaved
//! estimates), generalised to `m` estimates, two importance functions and two
//! jitter patterns so that jackknife, its ablations and Kettunen et al.'s
//! ray marching share one implementation.

use crate::lookup::LookupBatch;
use fogbank_math::{Pcg32, Ray, RaySegment};
use fogbank_volume::{Dda, SuperVoxel, VolumeAccess};

/// Largest number of interleaved estimates (unbiased ray marching draws up
/// to degree 8 + 1).
pub const MAX_ESTIMATES: usize = 9;

/// How samples are distributed along the ray within super-voxels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Importance {
    /// Peters 2025 Eq. 5, P = RMS(μ − μ_min), with the super-voxel minimum as
    /// control variate (its optical depth is added exactly).
    VarianceAware,
    /// Kettunen et al. 2021: the super-voxel mean, no control variate.
    Mean,
}

impl Importance {
    /// (importance P, control extinction μ_c) of a super-voxel.
    #[inline(always)]
    fn of(self, s: &SuperVoxel) -> (f64, f64) {
        match self {
            Importance::VarianceAware => (s.importance as f64, s.min as f64),
            Importance::Mean => (s.mean as f64, 0.0),
        }
    }
}

/// Peters 2025 §4.1: one independent jitter per stratum, or one jitter shared
/// by all strata of an estimate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Jitter {
    Stratified,
    Uniform,
}

/// Result of Alg. 2: the ray and importance it was prepared for, the total
/// importance along the ray and the tight segment covering the
/// super-voxels with non-zero importance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    pub ray: Ray,
    pub importance: Importance,
    /// F = ∫ P dt over the segment.
    pub total: f64,
    pub t_min: f32,
    pub t_max: f32,
}

/// Peters 2025, Alg. 2: one super-voxel traversal summing importance.
pub fn prepare<V: VolumeAccess>(v: &V, seg: &RaySegment, importance: Importance) -> Prepared {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let sv = v.supervoxels();
    let mut total = 0.0f64;
    let (mut t_min, mut t_max) = (t1, t0);
    for s in Dda::new(ray, sv.size as f32, sv.dims, t0, t1) {
        let (p, _) = importance.of(sv.get(s.cell));
        if p > 0.0 {
            total += (s.t1 - s.t0) as f64 * p;
            t_min = t_min.min(s.t0);
            t_max = t_max.max(s.t1);
        }
    }
    Prepared {
        ray: *ray,
        importance,
        total,
        t_min,
        t_max,
    }
}

/// Peters 2025, Alg. 1, for `out.len()` interleaved i.i.d. estimates with CDF
/// step `f_delta` (importance per stratum) along the prepared ray. Each estimate advances its own
/// normalised CDF cursor; every pass of the inner loop takes exactly one
/// full-resolution sample. Writes X_k = F_Δ Σ (μ − μ_c)/P + τ_c. The sample
/// points are known before any value is read, so they are read in batches
/// (`LookupBatch`, SIMD lanes), with the sequential result bit for bit.
pub fn estimates<V: VolumeAccess>(
    v: &V,
    prep: &Prepared,
    f_delta: f64,
    jitter: Jitter,
    rng: &mut Pcg32,
    lookups: &mut u32,
    out: &mut [f64],
) {
    let (ray, importance) = (&prep.ray, prep.importance);
    let m = out.len().min(MAX_ESTIMATES);
    out.iter_mut().for_each(|x| *x = 0.0);
    if m == 0 || prep.total <= 0.0 || f_delta <= 0.0 {
        return;
    }
    let sv = v.supervoxels();
    let mut cursor = [f64::INFINITY; MAX_ESTIMATES];
    for c in cursor.iter_mut().take(m) {
        *c = rng.next_f32() as f64;
    }
    let argmin = |c: &[f64; MAX_ESTIMATES]| (0..m).fold(0, |b, k| if c[k] < c[b] { k } else { b });
    let mut j = argmin(&cursor);
    let (mut f, mut tau_c) = (0.0f64, 0.0f64);
    let mut batch = LookupBatch::<(usize, f64, f64)>::default();
    for s in Dda::new(ray, sv.size as f32, sv.dims, prep.t_min, prep.t_max) {
        let (p, sigma_c) = importance.of(sv.get(s.cell));
        let len = (s.t1 - s.t0) as f64;
        tau_c += len * sigma_c;
        if p <= 0.0 {
            continue;
        }
        f += len * p;
        while f_delta * cursor[j] < f {
            // Rewind from the super-voxel's exit to the sample's CDF value.
            let t = (s.t1 as f64 - (f - f_delta * cursor[j]) / p).clamp(s.t0 as f64, s.t1 as f64);
            // The sample's σ_t is read later, with its batch; it adds
            // (σ_t − μ_c)/P to estimate j.
            if batch.push(v, ray.at(t as f32), (j, sigma_c, p), rng, lookups) {
                batch.drain(v, |sigma_t, (j, c, p)| out[j] += (sigma_t as f64 - c) / p);
            }
            cursor[j] = match jitter {
                // floor + 1 (not ceil) so a jitter of exactly 0 still moves on.
                Jitter::Stratified => floor_f64(cursor[j]) + 1.0 + rng.next_f32() as f64,
                Jitter::Uniform => cursor[j] + 1.0,
            };
            j = argmin(&cursor);
        }
    }
    batch.drain(v, |sigma_t, (j, c, p)| out[j] += (sigma_t as f64 - c) / p);
    for x in out.iter_mut().take(m) {
        *x = f_delta * *x + tau_c;
    }
}

/// `x.floor()`, bit for bit, without the `floor` call (the baseline x86-64
/// target has no rounding instruction) for 0 < x < 2⁵² (truncation is exact
/// there); zeros, negative values and NaN take `floor`.
#[inline(always)]
fn floor_f64(x: f64) -> f64 {
    if x > 0.0 && x < 4_503_599_627_370_496.0 {
        x as i64 as f64
    } else {
        x.floor()
    }
}

/// Exact optical depth of the control extinction (the super-voxel minima)
/// over `[t0, t1]`; used by estimators that add it separately.
pub fn control_optical_depth<V: VolumeAccess>(v: &V, seg: &RaySegment) -> f64 {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let sv = v.supervoxels();
    Dda::new(ray, sv.size as f32, sv.dims, t0, t1)
        .map(|s| (s.t1 - s.t0) as f64 * sv.get(s.cell).min as f64)
        .sum()
}

#[cfg(test)]
mod optical_depth_test {
    use super::floor_f64;
    use fogbank_math::Pcg32;

    #[test]
    fn floor_f64_matches_floor_bit_for_bit() {
        let mut xs = vec![
            0.0f64,
            -0.0,
            f64::MIN_POSITIVE,
            f64::from_bits(1),
            0.5,
            -0.5,
            1.0,
            4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9.3e18,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let mut rng = Pcg32::new(5, 8);
        for _ in 0..200_000 {
            let bits = (rng.next_u32() as u64) << 32 | rng.next_u32() as u64;
            xs.push(f64::from_bits(bits));
            xs.push(rng.next_f64() * 40.0 - 1.0);
        }
        for x in xs {
            assert_eq!(floor_f64(x).to_bits(), x.floor().to_bits(), "{x:e}");
        }
    }
}

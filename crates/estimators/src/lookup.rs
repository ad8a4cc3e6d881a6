//! The single place where estimators read the volume: counts the lookup and
//! draws the stochastic-filter jitter only when the filter uses it.

use fogbank_math::{pcg3d, rng::unit_f32, Pcg32, Vec3};
use fogbank_volume::VolumeAccess;

/// σ_t at index-space `p`, counting one full-resolution lookup. The jitter
/// for stochastic trilinear filtering is one PCG32 draw spread to three
/// dimensions by PCG3D (the GPU does the same).
#[inline(always)]
pub fn sigma_t_at<V: VolumeAccess>(v: &V, p: Vec3, rng: &mut Pcg32, lookups: &mut u32) -> f32 {
    let u = count_and_jitter(v, rng, lookups);
    v.sigma_t(p, u)
}

/// Counts one lookup and draws its stochastic-filter jitter (zero for
/// filters without one, drawing nothing).
#[inline(always)]
pub(crate) fn count_and_jitter<V: VolumeAccess>(v: &V, rng: &mut Pcg32, lookups: &mut u32) -> Vec3 {
    *lookups += 1;
    if v.needs_jitter() {
        let h = pcg3d([rng.next_u32(), *lookups, 0x9e37_79b9]);
        Vec3::new(unit_f32(h[0]), unit_f32(h[1]), unit_f32(h[2]))
    } else {
        Vec3::ZERO
    }
}

/// Lookups queued by a fixed-count estimator before it reads the volume.
pub const BATCH: usize = 32;

/// Lookups queued for one `VolumeAccess::sigma_t_lanes` call (grids
/// answer eight at a time in SIMD lanes). Each point counts
/// its lookup and draws its jitter when queued — the same random numbers in
/// the same order as `sigma_t_at` one point at a time — and `drain` hands
/// back the σ_t values in queue order, so an estimator that accumulates them
/// in that order gets bit for bit the sequential result. `P` is what the
/// caller needs to use a value (its estimate, its weight).
pub struct LookupBatch<P> {
    p: [Vec3; BATCH],
    u: [Vec3; BATCH],
    payload: [P; BATCH],
    len: usize,
}

impl<P: Copy + Default> Default for LookupBatch<P> {
    fn default() -> Self {
        LookupBatch {
            p: [Vec3::ZERO; BATCH],
            u: [Vec3::ZERO; BATCH],
            payload: [P::default(); BATCH],
            len: 0,
        }
    }
}

impl<P: Copy + Default> LookupBatch<P> {
    /// Queues σ_t at `p`; returns whether the batch is now full (the caller
    /// then drains it before queueing more).
    #[inline(always)]
    pub fn push<V: VolumeAccess>(
        &mut self,
        v: &V,
        p: Vec3,
        payload: P,
        rng: &mut Pcg32,
        lookups: &mut u32,
    ) -> bool {
        self.u[self.len] = count_and_jitter(v, rng, lookups);
        self.p[self.len] = p;
        self.payload[self.len] = payload;
        self.len += 1;
        self.len == BATCH
    }

    /// Reads every queued point and calls `f(σ_t, payload)` in queue order;
    /// leaves the batch empty.
    #[inline(always)]
    pub fn drain<V: VolumeAccess>(&mut self, v: &V, mut f: impl FnMut(f32, P)) {
        let n = self.len;
        if n == 0 {
            return;
        }
        let mut sigma = [0.0f32; BATCH];
        let u: &[Vec3] = if v.needs_jitter() { &self.u[..n] } else { &[] };
        v.sigma_t_lanes(&self.p[..n], u, &mut sigma[..n]);
        for (s, q) in sigma[..n].iter().zip(&self.payload[..n]) {
            f(*s, *q);
        }
        self.len = 0;
    }
}

/// Exponential free-flight distance with rate `sigma_maj`: −ln(1 − u)/σ̄.
#[inline(always)]
pub fn sample_exponential(rng: &mut Pcg32, sigma_maj: f32) -> f32 {
    -(1.0 - rng.next_f32()).ln() / sigma_maj
}

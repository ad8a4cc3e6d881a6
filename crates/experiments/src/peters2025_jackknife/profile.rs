//! Synthetic one-dimensional extinction profiles μ(t) (Peters 2025 Figs. 4–6,
//! Table 1) exposed as a [`VolumeAccess`], so that the project's own
//! optical-depth estimators (Alg. 1/2) march them unchanged along x.
//!
//! A profile is `n` voxel values reconstructed linearly between voxel centres
//! (1D trilinear, clamped at the ends). The linear reconstruction makes the
//! midpoint rule converge at 1/N² once steps are shorter than a voxel, the
//! effect Peters 2025 §4.1 attributes to equidistant sampling in Fig. 5, and its
//! exact optical depth is simply the sum of the voxel values.

use fogbank_estimators::optical_depth::{estimates, prepare, Importance, Jitter, Prepared};
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{SuperVoxelGrid, VolumeAccess};

/// Paper's Table 1 transmittance, T ≈ 0.13411: the smooth profile is scaled
/// to this optical depth so that Table 1's mean column is comparable.
pub const PAPER_TABLE1_T: f64 = 0.13411;

pub struct Profile1D {
    values: Vec<f64>,
    supervoxels: SuperVoxelGrid,
}

impl Profile1D {
    /// A profile from voxel values, with one super-voxel spanning all of it:
    /// then the Eq. 5 importance is constant, Alg. 1 places samples exactly
    /// like plain stratified (or uniform) jittered sampling, and the minimum
    /// control variate cancels (X = L/N Σ μ(t_j)), as in Peters 2025 §4.1.
    pub fn from_values(values: Vec<f64>) -> Self {
        let n = values.len() as u32;
        let mut p = Profile1D {
            values,
            supervoxels: SuperVoxelGrid::new(1, [0, 0, 0], Vec::new(), 1),
        };
        p.set_supervoxel_size(n);
        p
    }

    /// Rebuilds the super-voxel statistics (one-voxel apron for the linear
    /// reconstruction) for super-voxels of `size` voxels.
    pub fn set_supervoxel_size(&mut self, size: u32) {
        let n = self.values.len() as u32;
        let vals = &self.values;
        self.supervoxels = SuperVoxelGrid::build([n, 1, 1], size, 1, |i, _, _| {
            vals[i.clamp(0, n as i32 - 1) as usize] as f32
        });
    }

    /// Peters 2025 Fig. 4a-like: a smooth envelope carrying detail on every
    /// scale (fractional Brownian motion, Hurst ½, down to two voxels), so
    /// stratified sampling sees non-zero variance in every stratum. Scaled so
    /// that T = [`PAPER_TABLE1_T`].
    pub fn smooth() -> Self {
        let n = 2048usize;
        let mut rng = Pcg32::new(0x05ee_d000, 4);
        let fbm = fbm(n, 1024, 2, &mut rng);
        let values: Vec<f64> = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) / n as f64;
                // Two overlapping puffs, the second denser, fading to the ends.
                let env = 0.55 * bump(x, 0.3, 0.2) + 1.0 * bump(x, 0.68, 0.17) + 0.12;
                env * (3.5 * fbm[i]).exp()
            })
            .collect();
        Self::from_values(values).scaled_to_optical_depth(-PAPER_TABLE1_T.ln())
    }

    /// Peters 2025 Fig. 6-like: three narrow features on an empty background,
    /// so that at N = 20 only a few strata carry any variance.
    pub fn sparse() -> Self {
        let n = 2048usize;
        let values: Vec<f64> = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) / n as f64;
                let v = 1.0 * bump(x, 0.22, 0.012)
                    + 0.6 * bump(x, 0.47, 0.02)
                    + 1.4 * bump(x, 0.81, 0.008);
                if v < 1e-3 {
                    0.0
                } else {
                    v
                }
            })
            .collect();
        Self::from_values(values).scaled_to_optical_depth(1.0)
    }

    fn scaled_to_optical_depth(mut self, tau: f64) -> Self {
        let s = tau / self.optical_depth();
        self.values.iter_mut().for_each(|v| *v *= s);
        let size = self.supervoxels.size;
        self.set_supervoxel_size(size);
        self
    }

    /// Segment length L (voxel units).
    pub fn len(&self) -> f64 {
        self.values.len() as f64
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// μ(t), linear between voxel centres, constant in the outer half voxels.
    #[inline]
    pub fn sigma_t_at(&self, t: f64) -> f64 {
        let n = self.values.len();
        let q = (t - 0.5).clamp(0.0, (n - 1) as f64);
        let i = (q.floor() as usize).min(n.saturating_sub(2));
        let w = q - i as f64;
        if n == 1 {
            return self.values[0];
        }
        self.values[i] + w * (self.values[i + 1] - self.values[i])
    }

    /// Exact τ = ∫₀ᴸ μ(t) dt: each linear piece integrates to the mean of its
    /// end values, so the total is the sum of the voxel values.
    pub fn optical_depth(&self) -> f64 {
        self.values.iter().sum()
    }

    /// The ray the estimators march: along +x through the voxel row,
    /// t ∈ [0, L].
    pub fn ray(&self) -> Ray {
        Ray::new(Vec3::new(0.0, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0))
    }

    /// The profile prepared for the project's Alg. 1 along [`Profile1D::ray`]
    /// over its whole length, with the variance-aware importance.
    pub fn marching(&self) -> Marching<'_> {
        let ray = self.ray();
        let seg = RaySegment::new(ray, 0.0, self.len() as f32);
        let prep = prepare(self, &seg, Importance::VarianceAware);
        Marching {
            profile: self,
            prep,
        }
    }
}

/// A profile, its ray and Alg. 2's traversal of it: what every optical-depth
/// estimate along the profile needs.
pub struct Marching<'a> {
    profile: &'a Profile1D,
    /// Alg. 2's result; `prep.total / N` is the importance step of N samples.
    pub prep: Prepared,
}

impl Marching<'_> {
    /// Alg. 1: `out.len()` interleaved optical-depth estimates with
    /// importance step `f_delta` (variance-aware importance).
    #[inline]
    pub fn estimates(
        &self,
        f_delta: f64,
        jitter: Jitter,
        rng: &mut Pcg32,
        lookups: &mut u32,
        out: &mut [f64],
    ) {
        estimates(self.profile, &self.prep, f_delta, jitter, rng, lookups, out);
    }
}

impl VolumeAccess for Profile1D {
    #[inline]
    fn sigma_t(&self, p: Vec3, _u: Vec3) -> f32 {
        self.sigma_t_at(p.x as f64) as f32
    }
    fn needs_jitter(&self) -> bool {
        false
    }
    fn supervoxels(&self) -> &SuperVoxelGrid {
        &self.supervoxels
    }
    fn dims(&self) -> [u32; 3] {
        [self.values.len() as u32, 1, 1]
    }
}

/// A smooth bump exp(−((x − c)/w)²).
fn bump(x: f64, c: f64, w: f64) -> f64 {
    let z = (x - c) / w;
    (-z * z).exp()
}

/// Fractional Brownian motion (Hurst ½) on `n` samples from octaves of
/// linearly interpolated value noise with periods `max_period` … `min_period`
/// voxels and amplitude ∝ √period, normalised to unit peak magnitude. The
/// Hurst exponent ½ is what makes stratified sampling converge at ≈ 1/N
/// (RMSE ∝ N^{−(½+H)}), the rate Peters 2025 Fig. 5 shows.
fn fbm(n: usize, max_period: usize, min_period: usize, rng: &mut Pcg32) -> Vec<f64> {
    let mut out = vec![0.0; n];
    let mut period = max_period;
    while period >= min_period {
        let knots: Vec<f64> = (0..=n / period + 1)
            .map(|_| 2.0 * rng.next_f64() - 1.0)
            .collect();
        let amp = (period as f64 / max_period as f64).sqrt();
        for (i, o) in out.iter_mut().enumerate() {
            let x = i as f64 / period as f64;
            let k = x.floor() as usize;
            let w = x - k as f64;
            *o += amp * (knots[k] + w * (knots[k + 1] - knots[k]));
        }
        period /= 2;
    }
    let peak = out.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    out.iter_mut().for_each(|v| *v /= peak);
    out
}

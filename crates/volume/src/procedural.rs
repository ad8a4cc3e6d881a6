//! Procedural fractal cloud: fBm of gradient noise shaped by a soft
//! ellipsoidal envelope, with billowy detail from ridged octaves. Deterministic
//! in `(resolution, seed)`, so scenes and tests can name it instead of
//! shipping a file.

use crate::grid::{BrickGrid, Voxel};
use crate::Result;
use fogbank_math::{Pcg32, Vec3};

/// Improved gradient noise (Perlin 2002) with a permutation drawn from `seed`.
pub struct GradientNoise {
    perm: [u8; 512],
}

impl GradientNoise {
    pub fn new(seed: u64) -> Self {
        let mut p: [u8; 256] = std::array::from_fn(|i| i as u8);
        let mut rng = Pcg32::new(seed, 0x5eed);
        for i in (1..256).rev() {
            let j = (rng.next_u32() % (i as u32 + 1)) as usize;
            p.swap(i, j);
        }
        GradientNoise {
            perm: std::array::from_fn(|i| p[i & 255]),
        }
    }

    #[inline]
    fn grad(h: u8, x: f32, y: f32, z: f32) -> f32 {
        let h = h & 15;
        let u = if h < 8 { x } else { y };
        let v = if h < 4 {
            y
        } else if h == 12 || h == 14 {
            x
        } else {
            z
        };
        (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
    }

    /// Noise in roughly [−1, 1], zero at lattice points.
    pub fn noise(&self, p: Vec3) -> f32 {
        let f = p.floor();
        let (xi, yi, zi) = (
            (f.x as i32 & 255) as usize,
            (f.y as i32 & 255) as usize,
            (f.z as i32 & 255) as usize,
        );
        let (x, y, z) = (p.x - f.x, p.y - f.y, p.z - f.z);
        let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
        let (u, v, w) = (fade(x), fade(y), fade(z));
        let pm = &self.perm;
        let a = pm[xi] as usize + yi;
        let (aa, ab) = (pm[a] as usize + zi, pm[a + 1] as usize + zi);
        let b = pm[xi + 1] as usize + yi;
        let (ba, bb) = (pm[b] as usize + zi, pm[b + 1] as usize + zi);
        let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
        lerp(
            w,
            lerp(
                v,
                lerp(
                    u,
                    Self::grad(pm[aa], x, y, z),
                    Self::grad(pm[ba], x - 1.0, y, z),
                ),
                lerp(
                    u,
                    Self::grad(pm[ab], x, y - 1.0, z),
                    Self::grad(pm[bb], x - 1.0, y - 1.0, z),
                ),
            ),
            lerp(
                v,
                lerp(
                    u,
                    Self::grad(pm[aa + 1], x, y, z - 1.0),
                    Self::grad(pm[ba + 1], x - 1.0, y, z - 1.0),
                ),
                lerp(
                    u,
                    Self::grad(pm[ab + 1], x, y - 1.0, z - 1.0),
                    Self::grad(pm[bb + 1], x - 1.0, y - 1.0, z - 1.0),
                ),
            ),
        )
    }

    /// Fractal Brownian motion: `octaves` octaves, lacunarity 2, gain ½.
    pub fn fbm(&self, p: Vec3, octaves: u32) -> f32 {
        let (mut sum, mut amp, mut freq) = (0.0, 0.5, 1.0);
        for o in 0..octaves {
            // Offsetting each octave decorrelates the lattice zeros.
            sum += amp * self.noise(p * freq + Vec3::splat(o as f32 * 17.13));
            amp *= 0.5;
            freq *= 2.0;
        }
        sum
    }
}

/// Density of the cloud at normalised position `x ∈ [0, 1]³`, in [0, 1].
pub fn cloud_density(noise: &GradientNoise, x: Vec3) -> f32 {
    // Flattened ellipsoid sitting low in the box, like a cumulus.
    let q = (x - Vec3::new(0.5, 0.45, 0.5)) / Vec3::new(0.42, 0.32, 0.42);
    let r = q.length();
    let warp = Vec3::new(
        noise.fbm(x * 2.0 + Vec3::splat(3.1), 3),
        noise.fbm(x * 2.0 + Vec3::splat(7.7), 3),
        noise.fbm(x * 2.0 + Vec3::splat(1.3), 3),
    );
    let p = x * 5.0 + warp * 0.6;
    let billow = 1.0 - noise.fbm(p, 5).abs() * 2.0;
    let shape = 1.0 - r + 0.35 * billow - 0.2 + 0.35 * noise.fbm(x * 3.0, 4);
    // Flatter, denser base (clouds are cut at the condensation level).
    let base_cut = ((x.y - 0.18) * 12.0).clamp(0.0, 1.0);
    // Keeps the border voxels empty so the cloud never touches its box.
    let edge = x.min(Vec3::ONE - x).min_element();
    let border = ((edge - 0.03) / 0.08).clamp(0.0, 1.0);
    let d = (shape * 3.0).clamp(0.0, 1.0) * base_cut * border;
    let coverage = d * d * (3.0 - 2.0 * d);
    // Internal structure: wispy, high-frequency variation inside the body so
    // that rays see heterogeneous extinction, not a uniform block.
    let detail = (0.55 + 0.9 * noise.fbm(x * 11.0 + warp, 4)).clamp(0.05, 1.0);
    coverage * (0.25 + 0.75 * detail)
}

/// Samples `f` at the voxel centres `(i + ½)/res` of a `res³` grid: how
/// every procedural medium is rasterised.
pub fn rasterise<T: Voxel>(res: u32, f: impl Fn(Vec3) -> f32 + Sync) -> Result<BrickGrid<T>> {
    let inv = 1.0 / res as f32;
    BrickGrid::from_fn([res; 3], |i, j, k| {
        f((Vec3::new(i as f32, j as f32, k as f32) + Vec3::splat(0.5)) * inv)
    })
}

/// Rasterises the cloud into a `res³` grid.
pub fn cloud_grid<T: Voxel>(res: u32, seed: u64) -> Result<BrickGrid<T>> {
    let noise = GradientNoise::new(seed);
    rasterise(res, |x| cloud_density(&noise, x))
}

#[cfg(test)]
mod procedural_test {
    use super::*;

    #[test]
    fn cloud_is_deterministic_bounded_and_sparse_at_the_border() {
        let a = cloud_grid::<f32>(32, 7).unwrap();
        let b = cloud_grid::<f32>(32, 7).unwrap();
        let c = cloud_grid::<f32>(32, 8).unwrap();
        let (mut sum, mut differs, mut border) = (0.0, false, 0.0f32);
        for k in 0..32 {
            for j in 0..32 {
                for i in 0..32 {
                    let v = a.fetch(i, j, k);
                    assert!((0.0..=1.0).contains(&v));
                    assert_eq!(v, b.fetch(i, j, k));
                    differs |= v != c.fetch(i, j, k);
                    sum += v;
                    if i == 0 || j == 0 || k == 0 || i == 31 || j == 31 || k == 31 {
                        border = border.max(v);
                    }
                }
            }
        }
        assert!(differs);
        let fill = sum / 32f32.powi(3);
        assert!(fill > 0.05 && fill < 0.6, "fill {fill}");
        assert_eq!(border, 0.0);
    }
}

//! `cloud` media (pbrt's `CloudMedium`): pbrt's procedural density,
//! baked into a dense grid over its box `p0`–`p1`.
//!
//! The density at a point p of the medium's space is `CloudMedium::Density`:
//! the point scaled by `frequency`, displaced twice by pbrt's noise
//! gradient (`DNoise`, amplitude 0.05·`wispiness`, halving, at 10× then
//! 19.9× the frequency) when `wispiness` > 0, five octaves of Perlin noise
//! (`Noise`; amplitudes ½, ¼, …, frequencies ×1.99), then
//! clamp((1 − y)·4.5·`density`·noise, 0, 1) + 2·max(0, ½ − y), clamped to
//! [0, 1]. σ_a and σ_s scale it (the cloud has no `scale`).
//!
//! fogbank has no such procedural field, so the density is evaluated at
//! voxel centres and interpolated trilinearly: an approximation (a notice
//! gives the resolution) whose voxel is 1/(16·frequency) of the medium's
//! space (at most [`MAX_RES`] per axis), so the coarse octaves are resolved
//! and the finest (about 16× the frequency) are smoothed.

use super::grids::register;
use super::interpret::Placed;
use super::tables::set_array_density;
use super::warnings::Warnings;
use glam::DVec3;
use rayon::prelude::*;
use toml::Table;

/// The most voxels along an axis.
pub const MAX_RES: u32 = 128;

/// Ken Perlin's permutation of 0..=255 (his reference "improved noise"),
/// which pbrt's `NoisePerm` repeats.
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

fn perm(i: i32) -> i32 {
    PERM[(i & 255) as usize] as i32
}

/// The gradient of lattice point (x, y, z) dotted with the offset (pbrt's
/// `Grad`: one of Perlin's twelve edge directions, four repeated).
fn grad(x: i32, y: i32, z: i32, d: DVec3) -> f64 {
    let h = perm(perm(perm(x) + y) + z) & 15;
    let u = if h < 8 || h == 12 || h == 13 {
        d.x
    } else {
        d.y
    };
    let v = if h < 4 || h == 12 || h == 13 {
        d.y
    } else {
        d.z
    };
    (if h & 1 != 0 { -u } else { u }) + (if h & 2 != 0 { -v } else { v })
}

/// Perlin's quintic fade (pbrt's `NoiseWeight`).
fn fade(t: f64) -> f64 {
    t * t * t * (t * (6.0 * t - 15.0) + 10.0)
}

/// Perlin noise at p (pbrt's `Noise`).
pub fn noise(p: DVec3) -> f64 {
    let p = DVec3::new(p.x % 1073741824.0, p.y % 1073741824.0, p.z % 1073741824.0);
    let f = p.floor();
    let d = p - f;
    let [ix, iy, iz] = [f.x as i32 & 255, f.y as i32 & 255, f.z as i32 & 255];
    let w = |dx: i32, dy: i32, dz: i32| {
        let o = DVec3::new(dx as f64, dy as f64, dz as f64);
        grad(ix + dx, iy + dy, iz + dz, d - o)
    };
    let (wx, wy, wz) = (fade(d.x), fade(d.y), fade(d.z));
    let lerp = |t: f64, a: f64, b: f64| (1.0 - t) * a + t * b;
    let x00 = lerp(wx, w(0, 0, 0), w(1, 0, 0));
    let x10 = lerp(wx, w(0, 1, 0), w(1, 1, 0));
    let x01 = lerp(wx, w(0, 0, 1), w(1, 0, 1));
    let x11 = lerp(wx, w(0, 1, 1), w(1, 1, 1));
    lerp(wz, lerp(wy, x00, x10), lerp(wy, x01, x11))
}

/// pbrt's `DNoise`: the forward-difference gradient of [`noise`].
fn dnoise(p: DVec3) -> DVec3 {
    let delta = 0.01;
    let n = noise(p);
    let f = |o: DVec3| noise(p + o * delta);
    (DVec3::new(f(DVec3::X), f(DVec3::Y), f(DVec3::Z)) - DVec3::splat(n)) / delta
}

/// The cloud's shape parameters.
#[derive(Clone, Copy, Debug)]
pub struct Cloud {
    pub density: f64,
    pub wispiness: f64,
    pub frequency: f64,
}

impl Cloud {
    /// pbrt's `CloudMedium::Density` at p (medium space).
    pub fn density(&self, p: DVec3) -> f64 {
        // At or below y = 0 the altitude term alone reaches the clamp.
        if p.y <= 0.0 {
            return 1.0;
        }
        let mut pp = self.frequency * p;
        if self.wispiness > 0.0 {
            let (mut vomega, mut vlambda) = (0.05 * self.wispiness, 10.0);
            for _ in 0..2 {
                pp += vomega * dnoise(vlambda * pp);
                vomega *= 0.5;
                vlambda *= 1.99;
            }
        }
        let (mut d, mut omega, mut lambda) = (0.0, 0.5, 1.0);
        for _ in 0..5 {
            d += omega * noise(lambda * pp);
            omega *= 0.5;
            lambda *= 1.99;
        }
        let d = ((1.0 - p.y) * 4.5 * self.density * d).clamp(0.0, 1.0);
        (d + 2.0 * (0.5 - p.y).max(0.0)).clamp(0.0, 1.0)
    }
}

/// Voxels along each axis of the box `p0`–`p1` for frequency `f`.
pub fn resolution(p0: DVec3, p1: DVec3, f: f64) -> [u32; 3] {
    let e = (p1 - p0) * f.abs() * 16.0;
    [e.x, e.y, e.z].map(|x| (x.ceil() as u32).clamp(2, MAX_RES))
}

/// The `cloud` medium `m` (σ, albedo and phase already in `t`) baked into
/// an in-memory density grid.
pub fn cloud(m: &Placed, t: &mut Table, warnings: &mut Warnings) -> Result<(), String> {
    let ps = &m.entity.params;
    let num = |k: &str, d: f64| ps.float(k, d).map_err(|e| e.0);
    let c = Cloud {
        density: num("density", 1.0)?,
        wispiness: num("wispiness", 1.0)?,
        frequency: num("frequency", 5.0)?,
    };
    if ![c.density, c.wispiness, c.frequency]
        .iter()
        .all(|x| x.is_finite())
    {
        return Err("density, wispiness and frequency must be finite".into());
    }
    let point = |k: &str, d: DVec3| -> Result<DVec3, String> {
        Ok(ps.vec3(k).map_err(|e| e.0)?.map(DVec3::from).unwrap_or(d))
    };
    let (p0, p1) = (point("p0", DVec3::ZERO)?, point("p1", DVec3::ONE)?);
    if !((p1 - p0).cmpgt(DVec3::ZERO).all() && (p1 - p0).is_finite()) {
        return Err("needs finite p0 < p1 on every axis".into());
    }
    let n = resolution(p0, p1, c.frequency);
    let size = (p1 - p0) / DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
    let (nx, ny) = (n[0] as usize, n[1] as usize);
    let values: Vec<f64> = (0..nx * ny * n[2] as usize)
        .into_par_iter()
        .map(|i| {
            let ijk = DVec3::new(
                (i % nx) as f64,
                (i / nx % ny) as f64,
                (i / (nx * ny)) as f64,
            );
            c.density(p0 + (ijk + 0.5) * size)
        })
        .collect();
    let name = register(n, 1, &values, p0, p1, &format!("{} cloud", m.entity.loc))?;
    warnings.warn(format!(
        "{}: cloud: pbrt's procedural density is baked into a {}×{}×{} grid over its box and interpolated trilinearly (an approximation: detail finer than a voxel is smoothed)",
        m.entity.loc, n[0], n[1], n[2]
    ));
    set_array_density(t, name, m.ctm);
    Ok(())
}

//! Procedural animated smoke plume: a steady rising column whose turbulent
//! detail is carried by an analytic velocity field, so frame sequences with
//! deformation (Lin et al. 2021 §4.4, §5.2, Figs. 8, 9, 13) need no download.
//! Deterministic in `(resolution, seed, time)`.
//!
//! The velocity (in unit-cube lengths per second) is a constant rise plus a
//! rigid swirl about the column's vertical axis,
//! v(x) = (0, RISE, 0) + SWIRL · ŷ × (x − c),
//! whose flow map is known in closed form: the particle at `x` at time `t`
//! started at [`material_point`]`(x, t)`. The detail noise is read at the
//! material point, so it moves exactly with `v`; the column's envelope (a
//! cone widening upwards, fading at the top) stays put, as a steady plume's
//! does.

use crate::grid::{BrickGrid, Voxel};
use crate::procedural::GradientNoise;
use crate::Result;
use fogbank_math::Vec3;

/// Rise speed, unit-cube lengths per second.
pub const RISE: f32 = 0.15;
/// Swirl rate about the column axis, radians per second.
pub const SWIRL: f32 = 0.8;
/// The column axis passes through this point, vertically (+y).
const AXIS: Vec3 = Vec3::new(0.5, 0.0, 0.5);

/// Velocity at normalised position `x`, unit-cube lengths per second.
pub fn plume_velocity(x: Vec3) -> Vec3 {
    let d = x - AXIS;
    // ŷ × d = (d.z, 0, −d.x)
    Vec3::new(SWIRL * d.z, RISE, -SWIRL * d.x)
}

/// Where the particle at `x` at time `t` was at time 0 (the inverse flow
/// map of [`plume_velocity`]: undo the rise, rotate back about the axis).
pub fn material_point(x: Vec3, t: f32) -> Vec3 {
    let d = x - AXIS;
    let (s, c) = (SWIRL * t).sin_cos();
    Vec3::new(
        AXIS.x + d.x * c - d.z * s,
        x.y - RISE * t,
        AXIS.z + d.x * s + d.z * c,
    )
}

/// Density at normalised position `x` and time `t` (seconds), in [0, 1].
pub fn plume_density(noise: &GradientNoise, x: Vec3, t: f32) -> f32 {
    let radial = Vec3::new(x.x - AXIS.x, 0.0, x.z - AXIS.z).length();
    let radius = 0.07 + 0.3 * x.y;
    let m = material_point(x, t);
    let turbulence = noise.fbm(m * 4.0 + Vec3::splat(1.7), 5);
    let shape = 1.0 - radial / radius + 0.9 * turbulence;
    let d = (shape * 2.5).clamp(0.0, 1.0);
    // A source at the bottom, thinning with height as the smoke spreads.
    let source = ((x.y - 0.04) / 0.06).clamp(0.0, 1.0);
    let thinning = (1.0 - 0.7 * x.y).max(0.0);
    // Keeps the border voxels empty so the plume never touches its box.
    let edge = x.min(Vec3::ONE - x).min_element();
    let border = ((edge - 0.03) / 0.08).clamp(0.0, 1.0);
    let detail = (0.5 + 0.9 * noise.fbm(m * 12.0, 3)).clamp(0.05, 1.0);
    d * d * (3.0 - 2.0 * d) * source * thinning * border * detail
}

/// Rasterises the plume at time `t` into a `res³` grid (voxel centres at
/// `(i + ½)/res`).
pub fn plume_grid<T: Voxel>(res: u32, seed: u64, t: f32) -> Result<BrickGrid<T>> {
    let noise = GradientNoise::new(seed);
    crate::procedural::rasterise(res, |x| plume_density(&noise, x, t))
}

#[cfg(test)]
mod plume_test {
    use super::*;

    /// The material point is constant along particle paths: moving with
    /// the velocity for a short time leaves it unchanged to second order.
    #[test]
    fn material_points_are_carried_by_the_velocity() {
        let dt = 1e-3;
        for (i, x) in [
            Vec3::new(0.3, 0.2, 0.6),
            Vec3::new(0.7, 0.5, 0.45),
            Vec3::new(0.5, 0.9, 0.5),
        ]
        .into_iter()
        .enumerate()
        {
            let t = 0.4 * i as f32;
            let moved = x + plume_velocity(x) * dt;
            let (a, b) = (material_point(x, t), material_point(moved, t + dt));
            assert!((a - b).length() < 1e-5, "{x}: {a} vs {b}");
            assert!((material_point(x, 0.0) - x).length() < 1e-6);
        }
    }

    #[test]
    fn plume_moves_but_stays_in_its_box() {
        let res = 32;
        let a = plume_grid::<f32>(res, 5, 0.0).unwrap();
        let b = plume_grid::<f32>(res, 5, 0.25).unwrap();
        let (mut sum, mut changed, mut border) = (0.0f32, 0, 0.0f32);
        for k in 0..res as i32 {
            for j in 0..res as i32 {
                for i in 0..res as i32 {
                    let (u, v) = (a.fetch(i, j, k), b.fetch(i, j, k));
                    assert!((0.0..=1.0).contains(&u));
                    sum += u;
                    changed += ((u - v).abs() > 1e-3) as u32;
                    let last = res as i32 - 1;
                    if [i, j, k].iter().any(|&c| c == 0 || c == last) {
                        border = border.max(u);
                    }
                }
            }
        }
        let fill = sum / (res * res * res) as f32;
        assert!(fill > 0.01 && fill < 0.4, "fill {fill}");
        assert!(changed > 100, "only {changed} voxels changed over 0.25 s");
        assert_eq!(border, 0.0);
    }
}

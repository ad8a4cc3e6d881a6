//! Procedural explosion: a turbulent fireball whose density and temperature
//! come from one noise, so an emissive test volume (Lin et al. 2021's explosion
//! scenes) needs no download. Deterministic in `(resolution, seed)`.
//!
//! The fireball is a sphere displaced by fBm. Density is high in a sooty
//! shell and thinner in the core. Temperature (kelvin) peaks in the core at
//! about 3200 K and falls to 0 outside the fireball, so blackbody emission
//! glows from inside the smoke.

use crate::grid::{BrickGrid, Voxel};
use crate::procedural::GradientNoise;
use crate::Result;
use fogbank_math::Vec3;

/// What an explosion grid holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Density in [0, 1].
    Density,
    /// Temperature in kelvin.
    Temperature,
}

impl Quantity {
    pub fn parse(s: &str) -> Option<Quantity> {
        match s {
            "density" => Some(Quantity::Density),
            "temperature" => Some(Quantity::Temperature),
            _ => None,
        }
    }
}

/// How deep inside the fireball `x ∈ [0, 1]³` lies: > 0 inside, 1 at the
/// centre, displaced by turbulence.
fn depth(noise: &GradientNoise, x: Vec3) -> f32 {
    let q = x - Vec3::new(0.5, 0.46, 0.5);
    let turbulence = noise.fbm(x * 4.0 + Vec3::splat(2.7), 5);
    let billow = noise.fbm(x * 9.0 + Vec3::splat(5.1), 3).abs();
    let r = q.length() + 0.16 * turbulence - 0.05 * billow;
    // Keeps the border voxels empty so the fireball never touches its box.
    let edge = x.min(Vec3::ONE - x).min_element();
    let border = ((edge - 0.03) / 0.08).clamp(0.0, 1.0);
    (1.0 - r / 0.36).clamp(0.0, 1.0) * border
}

/// Density at normalised position `x`, in [0, 1].
pub fn explosion_density(noise: &GradientNoise, x: Vec3) -> f32 {
    let d = depth(noise, x);
    if d <= 0.0 {
        return 0.0;
    }
    // Soot thickest in a shell, thinner in the burning core.
    let shell = (d * 4.0).min(1.0) * (1.0 - 0.55 * d * d);
    let detail = (0.6 + 0.8 * noise.fbm(x * 14.0, 3)).clamp(0.1, 1.0);
    shell * detail
}

/// Temperature at normalised position `x`, in kelvin (0 outside).
pub fn explosion_temperature(noise: &GradientNoise, x: Vec3) -> f32 {
    let d = depth(noise, x);
    if d <= 0.0 {
        return 0.0;
    }
    let flicker = 0.85 + 0.3 * noise.fbm(x * 7.0 + Vec3::splat(9.3), 3);
    (500.0 + 2700.0 * d.powf(1.5) * flicker).max(0.0)
}

/// Rasterises `quantity` into a `res³` grid (voxel centres at `(i + ½)/res`).
pub fn explosion_grid<T: Voxel>(res: u32, seed: u64, quantity: Quantity) -> Result<BrickGrid<T>> {
    let noise = GradientNoise::new(seed);
    crate::procedural::rasterise(res, |x| match quantity {
        Quantity::Density => explosion_density(&noise, x),
        Quantity::Temperature => explosion_temperature(&noise, x),
    })
}

#[cfg(test)]
mod explosion_test {
    use super::*;

    #[test]
    fn density_and_temperature_share_their_support_and_the_core_is_hottest() {
        let res = 32;
        let rho = explosion_grid::<f32>(res, 3, Quantity::Density).unwrap();
        let temp = explosion_grid::<f32>(res, 3, Quantity::Temperature).unwrap();
        let again = explosion_grid::<f32>(res, 3, Quantity::Temperature).unwrap();
        let (mut inside, mut hot_core) = (0, 0.0f32);
        for k in 0..res as i32 {
            for j in 0..res as i32 {
                for i in 0..res as i32 {
                    let (d, t) = (rho.fetch(i, j, k), temp.fetch(i, j, k));
                    assert_eq!(t, again.fetch(i, j, k));
                    assert!((0.0..=1.0).contains(&d) && (0.0..4000.0).contains(&t));
                    // Both vanish together: emission only where there is medium.
                    assert_eq!(d > 0.0, t > 0.0, "voxel {i} {j} {k}: {d} {t}");
                    inside += (d > 0.0) as u32;
                    let centre = (i - 16).abs() + (j - 15).abs() + (k - 16).abs();
                    if centre <= 2 {
                        hot_core = hot_core.max(t);
                    }
                }
            }
        }
        let n = res * res * res;
        assert!(
            inside > n / 50 && inside < n / 2,
            "fireball fills {inside} of {n}"
        );
        assert!(hot_core > 2000.0, "core {hot_core} K");
        assert_eq!(rho.fetch(0, 0, 0), 0.0);
    }
}

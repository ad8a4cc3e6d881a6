//! Warps from the unit square to other domains, shared by BSDF and light
//! sampling.

use glam::Vec3;
use std::f32::consts::PI;

/// A uniform direction on the unit sphere (z uniform in [−1, 1]).
pub fn uniform_sphere(u: [f32; 2]) -> Vec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disk
/// (pbrt-v4 §A.5.1): uniform by area, with little distortion.
pub fn concentric_disk(u: [f32; 2]) -> (f32, f32) {
    let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    if a == 0.0 && b == 0.0 {
        (0.0, 0.0)
    } else if a.abs() > b.abs() {
        let phi = PI / 4.0 * (b / a);
        (a * phi.cos(), a * phi.sin())
    } else {
        let phi = PI / 2.0 - PI / 4.0 * (a / b);
        (b * phi.cos(), b * phi.sin())
    }
}

#[cfg(test)]
mod warp_test {
    use super::*;
    use crate::Pcg32;

    /// Chi-square over 8 sectors × 4 rings of equal area.
    #[test]
    fn concentric_disk_is_uniform() {
        let mut counts = [0u32; 32];
        let mut rng = Pcg32::new(3, 4);
        let n = 64_000;
        for _ in 0..n {
            let (x, y) = concentric_disk([rng.next_f32(), rng.next_f32()]);
            let r2 = x * x + y * y;
            assert!(r2 <= 1.0 + 1e-6);
            let ring = ((r2 * 4.0) as usize).min(3);
            let sector = (((y.atan2(x) / (2.0 * PI) + 1.0) * 8.0) as usize) % 8;
            counts[ring * 8 + sector] += 1;
        }
        let e = n as f64 / 32.0;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        // 31 degrees of freedom, α = 0.001.
        assert!(chi2 < 61.1, "χ² = {chi2}: {counts:?}");
    }
}

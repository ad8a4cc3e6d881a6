//! Procedural bunny-shaped cloud: Lin et al. 2021's Fig. 1 renders a cloud in the
//! shape of a bunny among emissive shapes; its VDB cannot be downloaded here,
//! so this builds one from a smooth union of ellipsoids (haunch, chest,
//! head, two ears, tail, paws) whose surface is eroded by the same billowy
//! fBm as `procedural::cloud_density`. Deterministic in `(resolution, seed)`.
//! The bunny sits on the floor of its box facing +x, ears up (+y).

use crate::grid::{BrickGrid, Voxel};
use crate::procedural::GradientNoise;
use crate::Result;
use fogbank_math::Vec3;

/// An ellipsoid part: centre and radii in the normalised box.
struct Part {
    centre: [f32; 3],
    radii: [f32; 3],
}

const PARTS: [Part; 9] = [
    // Haunch and chest make the body's teardrop.
    Part {
        centre: [0.36, 0.30, 0.5],
        radii: [0.22, 0.20, 0.21],
    },
    Part {
        centre: [0.56, 0.30, 0.5],
        radii: [0.17, 0.16, 0.16],
    },
    // Head, raised and forward.
    Part {
        centre: [0.72, 0.47, 0.5],
        radii: [0.13, 0.11, 0.11],
    },
    // Ears: long, thin, splayed.
    Part {
        centre: [0.70, 0.70, 0.44],
        radii: [0.05, 0.16, 0.065],
    },
    Part {
        centre: [0.64, 0.68, 0.57],
        radii: [0.05, 0.15, 0.065],
    },
    // Tail.
    Part {
        centre: [0.13, 0.35, 0.5],
        radii: [0.06, 0.06, 0.06],
    },
    // Front paws and the hind foot.
    Part {
        centre: [0.72, 0.14, 0.42],
        radii: [0.07, 0.05, 0.05],
    },
    Part {
        centre: [0.72, 0.14, 0.58],
        radii: [0.07, 0.05, 0.05],
    },
    Part {
        centre: [0.38, 0.12, 0.5],
        radii: [0.2, 0.06, 0.2],
    },
];

/// Approximate signed distance to one part (exact on the axes).
fn part_distance(p: &Part, x: Vec3) -> f32 {
    let r = Vec3::from(p.radii);
    let q = (x - Vec3::from(p.centre)) / r;
    (q.length() - 1.0) * r.min_element()
}

/// Polynomial smooth minimum (radius `k`), so the parts blend like a
/// sculpted body rather than a cluster of balls.
fn smooth_min(a: f32, b: f32, k: f32) -> f32 {
    let h = (0.5 + 0.5 * (b - a) / k).clamp(0.0, 1.0);
    b + (a - b) * h - k * h * (1.0 - h)
}

/// Signed distance to the bunny's smooth body, < 0 inside.
pub fn bunny_distance(x: Vec3) -> f32 {
    PARTS
        .iter()
        .map(|p| part_distance(p, x))
        .fold(f32::INFINITY, |a, b| {
            if a.is_infinite() {
                b
            } else {
                smooth_min(a, b, 0.04)
            }
        })
}

/// Density of the bunny cloud at normalised position `x ∈ [0, 1]³`, in [0, 1].
pub fn bunny_density(noise: &GradientNoise, x: Vec3) -> f32 {
    let warp = Vec3::new(
        noise.fbm(x * 3.0 + Vec3::splat(3.1), 3),
        noise.fbm(x * 3.0 + Vec3::splat(7.7), 3),
        noise.fbm(x * 3.0 + Vec3::splat(1.3), 3),
    );
    let billow = 1.0 - noise.fbm(x * 7.0 + warp * 0.5, 4).abs() * 2.0;
    // Billows erode the surface by up to a few percent of the box, small
    // enough that the ears survive.
    let shape = -bunny_distance(x) + 0.025 * billow - 0.01;
    let edge = x.min(Vec3::ONE - x).min_element();
    let border = ((edge - 0.02) / 0.04).clamp(0.0, 1.0);
    let d = (shape / 0.03).clamp(0.0, 1.0) * border;
    let coverage = d * d * (3.0 - 2.0 * d);
    let detail = (0.6 + 0.8 * noise.fbm(x * 12.0 + warp, 4)).clamp(0.08, 1.0);
    coverage * (0.3 + 0.7 * detail)
}

/// Rasterises the bunny into a `res³` grid.
pub fn bunny_grid<T: Voxel>(res: u32, seed: u64) -> Result<BrickGrid<T>> {
    let noise = GradientNoise::new(seed);
    crate::procedural::rasterise(res, |x| bunny_density(&noise, x))
}

#[cfg(test)]
mod bunny_test {
    use super::*;

    #[test]
    fn bunny_is_deterministic_bounded_and_empty_at_the_border() {
        let n = 40i32;
        let a = bunny_grid::<f32>(n as u32, 7).unwrap();
        let b = bunny_grid::<f32>(n as u32, 7).unwrap();
        let (mut sum, mut border) = (0.0, 0.0f32);
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let v = a.fetch(i, j, k);
                    assert!((0.0..=1.0).contains(&v));
                    assert_eq!(v, b.fetch(i, j, k));
                    sum += v;
                    if [i, j, k].iter().any(|&c| c == 0 || c == n - 1) {
                        border = border.max(v);
                    }
                }
            }
        }
        let fill = sum / (n as f32).powi(3);
        assert!(fill > 0.03 && fill < 0.4, "fill {fill}");
        assert_eq!(border, 0.0);
    }

    /// The shape is a bunny's: dense in the body, the head and both ears,
    /// empty between the ears and in front of the chest above the paws.
    #[test]
    fn bunny_has_body_head_and_two_ears() {
        let inside = |x: [f32; 3]| bunny_distance(Vec3::from(x)) < 0.0;
        assert!(inside([0.36, 0.30, 0.5]), "haunch");
        assert!(inside([0.72, 0.47, 0.5]), "head");
        assert!(inside([0.70, 0.78, 0.44]), "left ear");
        assert!(inside([0.64, 0.76, 0.57]), "right ear");
        assert!(!inside([0.67, 0.80, 0.505]), "gap between the ears");
        assert!(!inside([0.95, 0.30, 0.5]), "in front of the chest");
        assert!(!inside([0.36, 0.75, 0.5]), "above the back");
    }
}

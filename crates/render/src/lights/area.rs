//! One emitting triangle of a shape with an `area` emitter (Mitsuba's
//! `area`): constant radiance on the front side, sampled uniformly by
//! area. A shape's triangles are separate lights, so picking lights by
//! power picks its triangles by area, as Mitsuba samples a mesh emitter.

use fogbank_math::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaTriangle {
    pub p0: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
    /// Unit normal of the emitting side.
    pub n: Vec3,
    pub area: f32,
    pub radiance: Vec3,
}

/// Shadow rays toward a point on an emitter stop this fraction short of
/// it, so the emitter does not occlude itself.
pub const SHADOW_SHORTEN: f32 = 1e-4;

impl AreaTriangle {
    /// The triangle (p0, p1, p2) emitting `radiance` on the side of `n`
    /// (the winding's normal when `n` is zero); `None` when degenerate.
    pub fn new(p: [Vec3; 3], n: Vec3, radiance: Vec3) -> Option<AreaTriangle> {
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let c = e1.cross(e2);
        let area = 0.5 * c.length();
        if !(area > 0.0 && area.is_finite()) {
            return None;
        }
        let g = c / (2.0 * area);
        Some(AreaTriangle {
            p0: p[0],
            e1,
            e2,
            n: if g.dot(n) < 0.0 { -g } else { g },
            area,
            radiance,
        })
    }

    /// A uniform point (Heitz's low-distortion square-to-triangle map).
    pub fn sample_point(&self, u: [f32; 2]) -> Vec3 {
        let (b0, b1) = if u[0] < u[1] {
            let b0 = 0.5 * u[0];
            (b0, u[1] - b0)
        } else {
            let b1 = 0.5 * u[1];
            (u[0] - b1, b1)
        };
        self.p0 + b0 * self.e1 + b1 * self.e2
    }

    /// Radiance leaving toward `-wi` (zero behind the emitting side).
    pub fn le(&self, wi: Vec3) -> Vec3 {
        flat_le(self.n, self.radiance, wi)
    }

    /// Solid-angle density at `p` of sampling the point `q` of the
    /// triangle, seen along unit `wi`.
    pub fn pdf_solid(&self, p: Vec3, q: Vec3, wi: Vec3) -> f32 {
        flat_pdf_solid(self.n, self.area, p, q, wi)
    }
}

/// A flat one-sided emitter's radiance toward `-wi`: `radiance` on the side
/// of its normal `n`, zero behind.
pub fn flat_le(n: Vec3, radiance: Vec3, wi: Vec3) -> Vec3 {
    if n.dot(wi) < 0.0 {
        radiance
    } else {
        Vec3::ZERO
    }
}

/// Solid-angle density at `p` of sampling the point `q` of a flat emitter
/// of normal `n` and area `area` uniformly by area, seen along unit `wi`:
/// d² / (|cos θ_l| A).
pub fn flat_pdf_solid(n: Vec3, area: f32, p: Vec3, q: Vec3, wi: Vec3) -> f32 {
    let cos = n.dot(wi).abs();
    if cos <= 0.0 {
        return 0.0;
    }
    (q - p).length_squared() / (cos * area)
}

#[cfg(test)]
mod area_test {
    use super::*;

    #[test]
    fn points_are_uniform_and_inside() {
        let t = AreaTriangle::new(
            [
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            Vec3::Z,
            Vec3::ONE,
        )
        .unwrap();
        assert_eq!(t.area, 1.0);
        assert_eq!(t.n, Vec3::Z);
        // Chi-square over the 4 sub-triangles of equal area (midpoint split).
        let mut counts = [0u32; 4];
        let mut rng = fogbank_math::Pcg32::new(1, 2);
        let n = 40_000;
        for _ in 0..n {
            let q = t.sample_point([rng.next_f32(), rng.next_f32()]);
            let (a, b) = (q.x / 2.0, q.y);
            assert!(a >= 0.0 && b >= 0.0 && a + b <= 1.0 + 1e-6, "{q}");
            let k = if a > 0.5 {
                0
            } else if b > 0.5 {
                1
            } else if a + b < 0.5 {
                2
            } else {
                3
            };
            counts[k] += 1;
        }
        let e = n as f64 / 4.0;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        // 3 degrees of freedom, α = 0.001.
        assert!(chi2 < 16.27, "{counts:?}");
        assert_eq!(t.le(-Vec3::Z), Vec3::ONE);
        assert_eq!(t.le(Vec3::Z), Vec3::ZERO);
        assert!(AreaTriangle::new([Vec3::ZERO; 3], Vec3::Z, Vec3::ONE).is_none());
    }
}

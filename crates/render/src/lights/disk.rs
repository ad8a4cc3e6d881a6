//! An emitting analytic `disk` (Mitsuba's `area` emitter on a `disk`, an
//! ellipse under a non-uniform scale): constant radiance on the side of its
//! normal, sampled uniformly by area through the concentric map, as
//! Mitsuba 3's `Disk::sample_position`.

use super::area::{flat_le, flat_pdf_solid};
use fogbank_math::warp::concentric_disk;
use fogbank_math::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskLight {
    pub centre: Vec3,
    /// Images of the object-space x and y axes: the ellipse's half-axes.
    pub u: Vec3,
    pub v: Vec3,
    /// Unit normal of the emitting side.
    pub n: Vec3,
    pub area: f32,
    pub radiance: Vec3,
}

impl DiskLight {
    /// `None` when degenerate.
    pub fn new(centre: Vec3, u: Vec3, v: Vec3, n: Vec3, radiance: Vec3) -> Option<DiskLight> {
        let area = PI * u.cross(v).length();
        (area > 0.0 && area.is_finite()).then_some(DiskLight {
            centre,
            u,
            v,
            n,
            area,
            radiance,
        })
    }

    /// A uniform point.
    pub fn sample_point(&self, u: [f32; 2]) -> Vec3 {
        let (x, y) = concentric_disk(u);
        self.centre + x * self.u + y * self.v
    }

    /// Radiance leaving toward `-wi` (zero behind the emitting side).
    pub fn le(&self, wi: Vec3) -> Vec3 {
        flat_le(self.n, self.radiance, wi)
    }

    /// Solid-angle density at `p` of sampling the point `q`, seen along
    /// unit `wi`.
    pub fn pdf_solid(&self, p: Vec3, q: Vec3, wi: Vec3) -> f32 {
        flat_pdf_solid(self.n, self.area, p, q, wi)
    }
}

#[cfg(test)]
mod disk_test {
    use super::*;
    use fogbank_math::Pcg32;

    /// Points lie in the ellipse and E[1/pdf] is the solid angle the disk
    /// subtends on its axis, 2π(1 − h/√(h² + r²)).
    #[test]
    fn samples_cover_the_disk_solid_angle() {
        let l = DiskLight::new(
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::X,
            Vec3::Y,
            -Vec3::Z,
            Vec3::ONE,
        )
        .unwrap();
        assert!((l.area - PI).abs() < 1e-6);
        let p = Vec3::new(0.0, 0.0, -1.0);
        let mut rng = Pcg32::new(2, 7);
        let n = 40_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let q = l.sample_point([rng.next_f32(), rng.next_f32()]);
            assert!(q.x * q.x + q.y * q.y <= 1.0 + 1e-6 && q.z == 1.0);
            let wi = (q - p).normalize();
            assert_eq!(l.le(wi), Vec3::ONE);
            sum += 1.0 / l.pdf_solid(p, q, wi) as f64;
        }
        let exact = 2.0 * std::f64::consts::PI * (1.0 - 2.0 / 5f64.sqrt());
        assert!(
            (sum / n as f64 - exact).abs() < 0.01 * exact,
            "{}",
            sum / n as f64
        );
        assert_eq!(l.le(Vec3::Z * -1.0), Vec3::ZERO);
        assert!(DiskLight::new(Vec3::ZERO, Vec3::X, Vec3::X, Vec3::Z, Vec3::ONE).is_none());
    }
}

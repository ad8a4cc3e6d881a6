//! An emitting analytic `sphere` (Mitsuba's `area` emitter on a `sphere`):
//! constant radiance on the side its normals face. Seen from outside, the
//! outward-facing sphere is sampled uniformly in the cone of directions it
//! subtends (pbrt-v4 §6.2.4, Mitsuba 3's `Sphere::sample_direction`), which
//! wastes no sample on its far side; a sphere with `flip_normals` lights
//! only its inside, sampled uniformly by area from there.

use fogbank_math::warp::uniform_sphere;
use fogbank_math::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereLight {
    pub centre: Vec3,
    pub radius: f32,
    pub radiance: Vec3,
    /// Emits toward the centre (`flip_normals`).
    pub inward: bool,
}

/// Below sin²(1.5°) the cone's 1 − cos θ_max is taken from its Taylor
/// series: 1 − √(1 − s²) cancels in f32.
const SMALL_CONE: f32 = 0.000_685_23;

/// A point sampled on the light as seen from a receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpherePoint {
    pub q: Vec3,
    /// Solid-angle density at the receiver.
    pub pdf: f32,
}

impl SphereLight {
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// Whether `p` sees the emitting side: outside an outward sphere or
    /// inside an inward one.
    fn sees_front(&self, p: Vec3) -> bool {
        let outside = (p - self.centre).length_squared() > self.radius * self.radius;
        outside != self.inward
    }

    /// sin²θ_max and 1 − cos θ_max of the cone the sphere subtends from `p`
    /// (outside it).
    fn cone(&self, p: Vec3) -> (f32, f32) {
        let sin2_max = self.radius * self.radius / (p - self.centre).length_squared();
        let one_minus_cos = if sin2_max < SMALL_CONE {
            0.5 * sin2_max
        } else {
            1.0 - (1.0 - sin2_max).max(0.0).sqrt()
        };
        (sin2_max, one_minus_cos)
    }

    /// A point of the emitting side visible from `p` and its solid-angle
    /// pdf; `None` where `p` sees only the dark side.
    pub fn sample(&self, p: Vec3, u: [f32; 2]) -> Option<SpherePoint> {
        if !self.sees_front(p) {
            return None;
        }
        if self.inward {
            let q = self.centre + self.radius * uniform_sphere(u);
            let wi = (q - p).normalize_or_zero();
            let pdf = self.pdf_solid(p, q, wi);
            return (pdf > 0.0 && pdf.is_finite()).then_some(SpherePoint { q, pdf });
        }
        let (sin2_max, one_minus_cos) = self.cone(p);
        // θ uniform in cos over the cone, from the axis toward the centre.
        let (sin2, cos) = if sin2_max < SMALL_CONE {
            let s2 = sin2_max * u[0];
            (s2, (1.0 - s2).sqrt())
        } else {
            let c = 1.0 - u[0] * one_minus_cos;
            (1.0 - c * c, c)
        };
        // α: the angle at the centre between the axis back to p and the
        // point where the sampled direction meets the sphere.
        let sin_max = sin2_max.sqrt();
        let cos_alpha = sin2 / sin_max + cos * (1.0 - sin2 / sin2_max).max(0.0).sqrt();
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        let axis = (self.centre - p).normalize();
        let (s, t) = axis.any_orthonormal_pair();
        // The normal at the point faces back toward p's side.
        let n = -(s * (sin_alpha * phi.cos()) + t * (sin_alpha * phi.sin()) + axis * cos_alpha);
        let q = self.centre + self.radius * n;
        let pdf = 1.0 / (2.0 * PI * one_minus_cos);
        pdf.is_finite().then_some(SpherePoint { q, pdf })
    }

    /// Solid-angle density at `p` of [`SphereLight::sample`] returning the
    /// point `q` seen along unit `wi`.
    pub fn pdf_solid(&self, p: Vec3, q: Vec3, wi: Vec3) -> f32 {
        if !self.sees_front(p) {
            return 0.0;
        }
        if !self.inward {
            return 1.0 / (2.0 * PI * self.cone(p).1);
        }
        let cos = ((q - self.centre) / self.radius).dot(wi).abs();
        if cos <= 0.0 {
            return 0.0;
        }
        (q - p).length_squared() / (cos * self.area())
    }

    /// Radiance leaving `q` toward `-wi` (zero on the dark side).
    pub fn le(&self, q: Vec3, wi: Vec3) -> Vec3 {
        let out = (q - self.centre).dot(wi);
        if (out < 0.0) != self.inward {
            self.radiance
        } else {
            Vec3::ZERO
        }
    }
}

#[cfg(test)]
mod sphere_test {
    use super::*;
    use fogbank_math::Pcg32;

    /// Monte Carlo of the solid angle the sphere subtends: ∫ 1 dω = E[1/pdf]
    /// must equal 2π(1 − cos θ_max); every sample lies on the visible cap
    /// and its pdf is what pdf_solid reports. Near (cone sampling) and far
    /// (the Taylor branch).
    #[test]
    fn cone_samples_cover_the_visible_cap() {
        let mut rng = Pcg32::new(9, 3);
        for dist in [1.5f32, 3.0, 200.0] {
            let l = SphereLight {
                centre: Vec3::new(0.2, 0.1, -0.3),
                radius: 1.0,
                radiance: Vec3::ONE,
                inward: false,
            };
            let p = l.centre + Vec3::new(0.6, -0.48, 0.64) * dist;
            let sin2 = 1.0 / (dist * dist);
            let cap = 2.0 * PI * (1.0 - (1.0 - sin2 as f64).sqrt()) as f32;
            let n = 20_000;
            let mut sum = 0.0f64;
            for _ in 0..n {
                let s = l.sample(p, [rng.next_f32(), rng.next_f32()]).unwrap();
                assert!(((s.q - l.centre).length() - 1.0).abs() < 1e-4);
                let wi = (s.q - p).normalize();
                // Visible: the normal faces p.
                assert!((s.q - l.centre).dot(wi) <= 1e-3, "{s:?}");
                assert_eq!(l.le(s.q, wi), Vec3::ONE);
                assert!((l.pdf_solid(p, s.q, wi) - s.pdf).abs() <= 1e-6 * s.pdf);
                sum += 1.0 / s.pdf as f64;
            }
            let mean = sum / n as f64;
            assert!(
                ((mean as f32) - cap).abs() < 1e-3 * cap,
                "{dist}: {mean} vs {cap}"
            );
        }
    }

    /// The directions of the cone samples are uniform in the cone: a
    /// chi-square over rings of equal solid angle (cos θ) and sectors.
    #[test]
    fn cone_directions_chi_square() {
        let l = SphereLight {
            centre: Vec3::ZERO,
            radius: 1.0,
            radiance: Vec3::ONE,
            inward: false,
        };
        let p = Vec3::new(0.0, 0.0, 2.0);
        let cos_max = (1.0f32 - 0.25).sqrt();
        let mut rng = Pcg32::new(4, 8);
        let mut counts = [0u32; 24];
        let n = 48_000;
        for _ in 0..n {
            let s = l.sample(p, [rng.next_f32(), rng.next_f32()]).unwrap();
            let wi = (s.q - p).normalize();
            let ring = (((1.0 - -wi.z) / (1.0 - cos_max) * 4.0) as usize).min(3);
            let sector = (((wi.y.atan2(wi.x) / (2.0 * PI) + 1.0) * 6.0) as usize) % 6;
            counts[ring * 6 + sector] += 1;
        }
        let e = n as f64 / 24.0;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        // 23 degrees of freedom, α = 0.001.
        assert!(chi2 < 49.7, "χ² = {chi2}: {counts:?}");
    }

    #[test]
    fn inward_sphere_lights_only_its_inside() {
        let l = SphereLight {
            centre: Vec3::ZERO,
            radius: 2.0,
            radiance: Vec3::splat(3.0),
            inward: true,
        };
        assert!(l.sample(Vec3::new(0.0, 0.0, 5.0), [0.3, 0.6]).is_none());
        let p = Vec3::new(0.5, 0.0, 0.0);
        // Inside, E[1/pdf] is the full sphere of directions.
        let mut rng = Pcg32::new(1, 1);
        let n = 40_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let s = l.sample(p, [rng.next_f32(), rng.next_f32()]).unwrap();
            assert_eq!(l.le(s.q, (s.q - p).normalize()), Vec3::splat(3.0));
            sum += 1.0 / s.pdf as f64;
        }
        let four_pi = 4.0 * std::f64::consts::PI;
        assert!(
            (sum / n as f64 - four_pi).abs() < 0.02 * four_pi,
            "{}",
            sum / n as f64
        );
        let outward = SphereLight { inward: false, ..l };
        assert!(outward.sample(p, [0.3, 0.6]).is_none());
        assert_eq!(outward.pdf_solid(p, Vec3::X * 2.0, Vec3::X), 0.0);
    }
}

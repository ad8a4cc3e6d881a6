//! The Trowbridge–Reitz (GGX) microfacet distribution with Smith's
//! height-correlated masking (pbrt-v4 §9.6, Mitsuba 3's `MicrofacetDistribution`
//! with `sample_visible = true`), isotropic roughness α. Directions are in
//! the local frame, z along the macro-normal; microfacet normals lie in the
//! upper hemisphere.

use glam::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    pub alpha: f32,
}

impl Ggx {
    /// α below this is treated as smooth by the BSDFs (a delta lobe), as in
    /// pbrt-v4: the sampled density would not be representable.
    pub const SMOOTH: f32 = 1e-3;

    /// D(wm): the microfacet normal density, ∫ D(wm) cos θm dwm = 1.
    pub fn d(&self, wm: Vec3) -> f32 {
        let cos2 = wm.z * wm.z;
        if cos2 <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        let e = 1.0 + tan2 / a2;
        1.0 / (PI * a2 * cos2 * cos2 * e * e)
    }

    /// Smith's Λ(w).
    pub fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::INFINITY;
        }
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        0.5 * ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0)
    }

    /// G1(w): masking of one direction.
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// G(wo, wi) = G1(wo) G1(wi): separable masking–shadowing, Mitsuba 3's
    /// form (pbrt-v4 uses the height-correlated 1 / (1 + Λo + Λi); the
    /// Mitsuba scenes fogbank is checked against use this one).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.g1(wo) * self.g1(wi)
    }

    /// Density of visible normals seen from `w` (mirrored to the upper side
    /// when below it, as [`Ggx::sample_visible`] does):
    /// G1(w) max(0, ±w·wm) D(wm) / |cos θ_w| — the pdf of
    /// [`Ggx::sample_visible`] in solid angle of wm.
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        let cos = w.z.abs();
        if cos == 0.0 {
            return 0.0;
        }
        let facing = (w.dot(wm) * w.z.signum()).max(0.0);
        self.g1(w) / cos * self.d(wm) * facing
    }

    /// A microfacet normal visible from `w` (Heitz 2018; `w` below the
    /// surface is mirrored up first), from two uniform numbers.
    pub fn sample_visible(&self, w: Vec3, u: [f32; 2]) -> Vec3 {
        let a = self.alpha;
        let mut wh = Vec3::new(a * w.x, a * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        let t1 = if wh.z < 0.99999 {
            Vec3::Z.cross(wh).normalize()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        // Uniform point on the disk, then warped to the projected
        // hemisphere seen from wh.
        let r = u[0].sqrt();
        let phi = 2.0 * PI * u[1];
        let px = r * phi.cos();
        let py0 = r * phi.sin();
        let h = (1.0 - px * px).max(0.0).sqrt();
        let s = 0.5 * (1.0 + wh.z);
        let py = (1.0 - s) * h + s * py0;
        let pz = (1.0 - px * px - py * py).max(0.0).sqrt();
        let nh = px * t1 + py * t2 + pz * wh;
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod microfacet_test {
    use super::*;
    use fogbank_math::Pcg32;

    /// ∫ D cos θm dwm = 1 and, for every view, ∫ D_visible dwm = 1
    /// (midpoint rule over the hemisphere).
    #[test]
    fn densities_normalise() {
        for alpha in [0.05f32, 0.3, 0.8] {
            let g = Ggx { alpha };
            let n = 1200;
            let (mut proj, mut vis) = (0.0f64, 0.0f64);
            let w = Vec3::new(0.6, 0.0, 0.8);
            // cos θ = 1 − t² spreads points towards the peak at θ = 0.
            for i in 0..n {
                let t = (i as f64 + 0.5) / n as f64;
                let c = 1.0 - t * t;
                let dc = 2.0 * t / n as f64;
                let s = (1.0 - c * c).max(0.0).sqrt();
                for j in 0..64 {
                    let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / 64.0;
                    let wm = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                    let dw = dc * 2.0 * std::f64::consts::PI / 64.0;
                    proj += g.d(wm) as f64 * c * dw;
                    vis += g.d_visible(w, wm) as f64 * dw;
                }
            }
            assert!((proj - 1.0).abs() < 2e-3, "α {alpha}: ∫D cos = {proj}");
            assert!((vis - 1.0).abs() < 2e-3, "α {alpha}: ∫D_vis = {vis}");
        }
    }

    #[test]
    fn visible_normals_face_the_viewer() {
        let g = Ggx { alpha: 0.5 };
        let mut rng = Pcg32::new(1, 2);
        for _ in 0..10_000 {
            let w = Vec3::new(0.9, 0.1, 0.2).normalize();
            let wm = g.sample_visible(w, [rng.next_f32(), rng.next_f32()]);
            assert!(wm.z > 0.0 && w.dot(wm) >= -1e-4 && (wm.length() - 1.0).abs() < 1e-5);
        }
    }
}

//! Smooth plastic, as Mitsuba 3's `plastic`: a smooth dielectric coating
//! (delta reflection with the Fresnel term, tinted by `specular`) over a
//! Lambertian base whose light crosses the coating twice and bounces
//! inside it: f = ρ′ (1 − F(θi)) (1 − F(θo)) / (π η²) with
//! ρ′ = ρ / (1 − F_dr) (or ρ / (1 − ρ F_dr) when `nonlinear`), F_dr the
//! coating's internal diffuse Fresnel reflectance. The lobe is chosen with
//! Mitsuba's probabilities (Fresnel times the specular/diffuse mean
//! weights), so sample streams and weights match its. One-sided.

use super::fresnel::dielectric as fresnel;
use super::sample::{sample_cosine, BsdfSample};
use glam::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Interior over exterior IOR (Mitsuba: `int_ior / ext_ior`, by
    /// default 1.49 / 1.000277).
    pub eta: f32,
    pub nonlinear: bool,
}

/// The diffuse Fresnel reflectance of an interface with relative IOR
/// `eta` (Mitsuba's `fresnel_diffuse_reflectance`: Egan and Hilgeman's fit
/// below 1, d'Eon and Irving's above).
pub fn diffuse_fresnel(eta: f32) -> f32 {
    let inv = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv + eta * (eta * -1.4399 + 0.7099) + 0.6681
    } else {
        // Horner in 1/η: 0.919317 − 3.4793 x + 6.75335 x² − 7.80989 x³
        // + 4.98554 x⁴ − 1.36881 x⁵.
        let c = [0.919317f32, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881];
        c.iter().rev().fold(0.0, |acc, &k| acc * inv + k)
    }
}

fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) / 3.0
}

impl Plastic {
    /// Probability of the specular lobe for incident cosine `cos_o`.
    fn specular_probability(&self, f_o: f32) -> f32 {
        let (d, s) = (mean(self.diffuse), mean(self.specular));
        let w = s / (d + s);
        let ps = f_o * w;
        let pd = (1.0 - f_o) * (1.0 - w);
        ps / (ps + pd)
    }

    /// ρ′ (1 − F(θi)) (1 − F(θo)) / (π η²) for `wo`, `wi` above.
    fn diffuse_value(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let fdr = diffuse_fresnel(1.0 / self.eta);
        let base = if self.nonlinear {
            self.diffuse / (Vec3::ONE - self.diffuse * fdr)
        } else {
            self.diffuse / (1.0 - fdr)
        };
        let (f_o, f_i) = (fresnel(wo.z, self.eta), fresnel(wi.z, self.eta));
        base * ((1.0 - f_o) * (1.0 - f_i) / (PI * self.eta * self.eta))
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.diffuse_value(wo, wi)
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        (1.0 - self.specular_probability(fresnel(wo.z, self.eta))) * wi.z / PI
    }

    pub fn sample(&self, wo: Vec3, uc: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f_o = fresnel(wo.z, self.eta);
        let ps = self.specular_probability(f_o);
        if uc < ps {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample {
                wi,
                f: self.specular * f_o / wi.z,
                pdf: ps,
                delta: true,
            });
        }
        let wi = sample_cosine(u);
        if wi.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            f: self.diffuse_value(wo, wi),
            pdf: (1.0 - ps) * wi.z / PI,
            delta: false,
        })
    }
}

#[cfg(test)]
mod plastic_test {
    use super::*;

    /// Mitsuba's fits at their reference points: F_dr(1/1.5) (inside glass)
    /// ≈ 0.596 and F_dr(1.5) ≈ 0.092 (known values of the hemispherical
    /// Fresnel average to within the fits' stated 0.1–0.6 %).
    #[test]
    fn diffuse_fresnel_fits() {
        assert!(
            (diffuse_fresnel(1.0 / 1.5) - 0.596).abs() < 0.005,
            "{}",
            diffuse_fresnel(1.0 / 1.5)
        );
        assert!(
            (diffuse_fresnel(1.5) - 0.092).abs() < 0.003,
            "{}",
            diffuse_fresnel(1.5)
        );
    }
}

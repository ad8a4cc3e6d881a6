//! The Henyey–Greenstein phase function (Henyey & Greenstein 1941), the
//! one-parameter model of anisotropic scattering used for clouds and smoke;
//! g = 0 is isotropic scattering.
//!
//! # Conventions
//!
//! * `cos_theta` in [`HenyeyGreenstein::eval`] is the cosine of the
//!   *scattering angle*: the angle between the direction a photon travels
//!   before the collision and the direction it travels after. With this
//!   (physics) convention g is the mean cosine ⟨cos θ⟩, and g > 0 is forward
//!   scattering: a photon travelling along d most likely keeps travelling
//!   along d.
//! * `wo` and `wi` follow pbrt-v4 (§11.3): both point *away* from the
//!   scattering point. `wo` points back towards where the path came from (for
//!   a ray travelling along `ray.d`, `wo = -ray.d`), and `wi` is the new
//!   direction to trace. The scattering angle is therefore the angle between
//!   `-wo` and `wi`, so `pdf(wo, wi) = eval(dot(-wo, wi))`. (pbrt-v4's
//!   `HenyeyGreenstein(cosTheta, g)` takes `dot(wo, wi)` instead and flips
//!   the sign inside; this module never does that.)
//! * The value is normalised over the sphere, so it is also the pdf of
//!   [`HenyeyGreenstein::sample`] in solid angle.
//!
//! # Accuracy near |g| → 1
//!
//! The textbook forms 1 + g² − 2g cos θ and
//! cos θ = (1 + g² − s²) / (2g) cancel catastrophically in f32 when the lobe
//! is narrow (g = 0.999: the lobe is 10⁻³ rad wide and 1 − cos θ ≈ 5·10⁻⁷)
//! and divide by zero at g = 0. Everything here is written in the
//! algebraically equal forms that sum non-negative terms only, using
//! 1 − cos θ and 1 + cos θ directly (derived from the standard inversion of
//! the HG cdf, pbrt-v4 §11.3.1), so no special case for g = 0 is needed.

use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

const INV_4PI: f32 = 1.0 / (4.0 * PI);

/// Henyey–Greenstein phase function with asymmetry parameter `g` ∈ (−1, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    pub g: f32,
}

impl HenyeyGreenstein {
    /// Isotropic scattering, 1/(4π) in every direction.
    pub const ISOTROPIC: HenyeyGreenstein = HenyeyGreenstein { g: 0.0 };

    /// Phase function value (= pdf per steradian) for the scattering angle
    /// with cosine `cos_theta` (physics convention, see the module docs):
    /// (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}).
    ///
    /// An f32 cosine near ±1 is quantised in steps of 6·10⁻⁸, coarse
    /// against the lobe of |g| ≳ 0.99 (about 5·10⁻⁷ wide in cos θ at
    /// g = 0.999); [`HenyeyGreenstein::pdf`] takes the directions themselves
    /// and has no such limit, so prefer it for very peaked lobes.
    #[inline]
    pub fn eval(&self, cos_theta: f32) -> f32 {
        let c = cos_theta.clamp(-1.0, 1.0);
        self.eval_split(1.0 - c, 1.0 + c)
    }

    /// Solid-angle pdf of scattering into `wi` given `wo` (both unit, both
    /// pointing away from the scattering point; see the module docs).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        // For unit vectors, 1 ∓ dot(−wo, wi) = |wi ± wo|² / 2, which stays
        // accurate where the dot product itself has lost its digits.
        let one_minus_cos = 0.5 * (wi + wo).length_squared();
        let one_plus_cos = 0.5 * (wi - wo).length_squared();
        self.eval_split(one_minus_cos, one_plus_cos)
    }

    /// Samples the new direction `wi` given `wo` (pointing away from the
    /// scattering point, i.e. `-ray.d`) and returns it with its solid-angle
    /// pdf. `u[0]` picks the scattering angle, `u[1]` the azimuth.
    ///
    /// The scattering angle inverts the HG cdf (pbrt-v4 §11.3.1): with
    /// D = 1 + g − 2gξ and s = (1 − g²)/D, the textbook result is
    /// cos θ = (1 + g² − s²)/(2g). Here it is rearranged into
    /// 1 − cos θ = (1 − g) ξ (s + 1 − g) / D and
    /// 1 + cos θ = (1 + g)(1 − ξ)(s + 1 + g) / D, both sums of non-negative
    /// terms, with sin²θ = (1 − cos θ)(1 + cos θ); and since
    /// 1 + g² − 2g cos θ = s², the pdf is D³ / (4π (1 − g²)²).
    #[inline]
    pub fn sample(&self, wo: Vec3, u: [f32; 2]) -> (Vec3, f32) {
        let g = self.g;
        let xi = u[0];
        let (one_minus_g, one_plus_g) = (1.0 - g, 1.0 + g);
        let one_minus_g2 = one_minus_g * one_plus_g;
        // D = 1 + g − 2gξ, written as a sum of non-negative terms.
        let d = if g >= 0.0 {
            one_minus_g + 2.0 * g * (1.0 - xi)
        } else {
            one_plus_g - 2.0 * g * xi
        };
        let s = one_minus_g2 / d;
        let one_minus_cos = one_minus_g * xi * (s + one_minus_g) / d;
        let one_plus_cos = one_plus_g * (1.0 - xi) * (s + one_plus_g) / d;
        let cos_theta = if one_minus_cos <= one_plus_cos {
            1.0 - one_minus_cos
        } else {
            one_plus_cos - 1.0
        };
        let sin_theta = (one_minus_cos * one_plus_cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        let forward = -wo;
        let (t1, t2) = forward.any_orthonormal_pair();
        let wi = (t1 * phi.cos() + t2 * phi.sin()) * sin_theta + forward * cos_theta;
        let pdf = INV_4PI * d * d * d / (one_minus_g2 * one_minus_g2);
        (wi, pdf)
    }

    /// The phase function from 1 − cos θ and 1 + cos θ: the denominator
    /// 1 + g² − 2g cos θ equals (1 − g)² + 2g(1 − cos θ) and
    /// (1 + g)² − 2g(1 + cos θ); the form whose terms are both non-negative
    /// for the sign of g is used.
    #[inline]
    fn eval_split(&self, one_minus_cos: f32, one_plus_cos: f32) -> f32 {
        let g = self.g;
        let (one_minus_g, one_plus_g) = (1.0 - g, 1.0 + g);
        let denom = if g >= 0.0 {
            one_minus_g * one_minus_g + 2.0 * g * one_minus_cos
        } else {
            one_plus_g * one_plus_g - 2.0 * g * one_plus_cos
        };
        INV_4PI * one_minus_g * one_plus_g / (denom * denom.sqrt())
    }
}

/// `phase = { type = "hg" | "isotropic", g = 0 }`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PhaseDesc {
    #[serde(rename = "type")]
    pub ty: String,
    #[serde(default)]
    pub g: f32,
}

impl Default for PhaseDesc {
    fn default() -> Self {
        PhaseDesc {
            ty: "hg".into(),
            g: 0.0,
        }
    }
}

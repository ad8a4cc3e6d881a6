//! Fresnel reflectance for dielectrics (real relative IOR) and conductors
//! (complex IOR η + ik per channel), and Snell refraction — pbrt-v4 §9.3,
//! Mitsuba 3's `fresnel`. `eta` is the IOR of the side the normal points
//! away from (inside) over the side it points into (outside).

use glam::Vec3;

/// Unpolarised Fresnel reflectance of a dielectric interface for incident
/// cosine `cos_i` (negative: arriving from inside, where the relative IOR
/// is 1/η). Total internal reflection gives 1.
pub fn dielectric(cos_i: f32, eta: f32) -> f32 {
    let (mut cos_i, mut eta) = (cos_i.clamp(-1.0, 1.0), eta);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    fn new(re: f32, im: f32) -> Complex {
        Complex { re, im }
    }
    fn mul(self, o: Complex) -> Complex {
        Complex::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn sub(self, o: Complex) -> Complex {
        Complex::new(self.re - o.re, self.im - o.im)
    }
    fn add(self, o: Complex) -> Complex {
        Complex::new(self.re + o.re, self.im + o.im)
    }
    fn norm2(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    fn div(self, o: Complex) -> Complex {
        let d = o.norm2();
        Complex::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    /// Principal square root.
    fn sqrt(self) -> Complex {
        let n = self.norm2().sqrt();
        if n == 0.0 {
            return Complex::new(0.0, 0.0);
        }
        let t1 = (0.5 * (n + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            Complex::new(t1, t2)
        } else {
            Complex::new(t2.abs(), t1.copysign(self.im))
        }
    }
}

/// Fresnel reflectance of a conductor with complex IOR `eta + i k` for
/// incident cosine `cos_i` ≥ 0 (pbrt-v4's `FrComplex`).
fn conductor1(cos_i: f32, eta: f32, k: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let e = Complex::new(eta, k);
    let ci = Complex::new(cos_i, 0.0);
    let sin2_i = Complex::new(1.0 - cos_i * cos_i, 0.0);
    let sin2_t = sin2_i.div(e.mul(e));
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let r_parl = e.mul(ci).sub(cos_t).div(e.mul(ci).add(cos_t));
    let r_perp = ci.sub(e.mul(cos_t)).div(ci.add(e.mul(cos_t)));
    0.5 * (r_parl.norm2() + r_perp.norm2())
}

/// Per-channel conductor reflectance.
pub fn conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    Vec3::new(
        conductor1(cos_i, eta.x, k.x),
        conductor1(cos_i, eta.y, k.y),
        conductor1(cos_i, eta.z, k.z),
    )
}

/// Refracts `wi` (pointing away from the surface) through normal `n` with
/// relative IOR `eta`; `None` under total internal reflection. Returns the
/// transmitted direction and the relative IOR actually crossed (η, or 1/η
/// when `wi` is on the side `n` points away from).
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let (mut n, mut eta) = (n, eta);
    let mut cos_i = n.dot(wi);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wi / eta + (cos_i / eta - cos_t) * n, eta))
}

/// Mirror of `w` about `n`.
pub fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    -w + 2.0 * w.dot(n) * n
}

#[cfg(test)]
mod fresnel_test {
    use super::*;

    #[test]
    fn known_values() {
        // Normal incidence: ((η − 1)/(η + 1))², glass 4 %.
        assert!((dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        // Symmetric at normal incidence from inside; TIR beyond the
        // critical angle (sin θ > 1/1.5).
        assert!((dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(dielectric(-0.5, 1.5), 1.0);
        // Grazing: 1. Index-matched: 0.
        assert!((dielectric(1e-6, 1.5) - 1.0).abs() < 1e-3);
        assert!(dielectric(0.3, 1.0).abs() < 1e-7);
        // A conductor with k = 0 is a dielectric.
        for c in [0.1f32, 0.5, 0.9, 1.0] {
            assert!((conductor1(c, 1.5, 0.0) - dielectric(c, 1.5)).abs() < 1e-5);
        }
        // Gold-like at normal incidence: ((n−1)² + k²)/((n+1)² + k²).
        let (n, k) = (0.18f32, 3.42f32);
        let want = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        assert!((conductor1(1.0, n, k) - want).abs() < 1e-5);
    }

    #[test]
    fn refraction_obeys_snell_and_round_trips() {
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let (wt, eta) = refract(wi, Vec3::Z, 1.33).unwrap();
        assert_eq!(eta, 1.33);
        assert!((wt.length() - 1.0).abs() < 1e-6 && wt.z < 0.0);
        // sin θt = sin θi / η.
        assert!((wt.x.abs() - 0.6 / 1.33).abs() < 1e-6);
        let (back, _) = refract(wt, Vec3::Z, 1.33).unwrap();
        assert!((back - wi).length() < 1e-5);
        // Total internal reflection from inside at a steep angle.
        assert!(refract(Vec3::new(0.9, 0.0, -0.4359), Vec3::Z, 1.5).is_none());
    }
}

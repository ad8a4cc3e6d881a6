//! Microfacet normal distributions, as Mitsuba 3's `MicrofacetDistribution`
//! (isotropic roughness α): Trowbridge–Reitz (GGX) and Beckmann, with
//! Smith's separable masking G(wo, wi) = G1(wo) G1(wi), and normals sampled
//! either from the distribution of normals visible from the incident
//! direction (`sample_visible`, Mitsuba's default; Heitz and d'Eon 2014) or
//! from D(m) cos θm. Directions are in the local frame, z along the
//! macro-normal; microfacet normals lie in the upper hemisphere.
//!
//! The BSDFs' masking G1 is Mitsuba's: exact for GGX, Walter et al.'s
//! rational fit for Beckmann (relative error < 0.35 %), so that the models
//! are the ones Mitsuba renders. The density of visible normals is exact
//! (Beckmann's Λ through erfc), because it is the density the sampler
//! draws from and MIS and the estimator divide by it.

use fogbank_math::erf::{erf, erfc, erfinv};
use glam::Vec3;
use std::f32::consts::PI;

/// Which distribution of microfacet normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distribution {
    Ggx,
    Beckmann,
}

impl Distribution {
    pub fn name(self) -> &'static str {
        match self {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    pub distribution: Distribution,
    pub alpha: f32,
    /// Sample visible normals (else normals from D(m) cos θm).
    pub sample_visible: bool,
}

impl Microfacet {
    /// α below this is treated as smooth by the BSDFs (a delta lobe), as in
    /// pbrt-v4: the sampled density would not be representable.
    pub const SMOOTH: f32 = 1e-3;

    /// GGX with visible-normal sampling.
    pub fn ggx(alpha: f32) -> Microfacet {
        Microfacet {
            distribution: Distribution::Ggx,
            alpha,
            sample_visible: true,
        }
    }

    /// Beckmann with visible-normal sampling.
    pub fn beckmann(alpha: f32) -> Microfacet {
        Microfacet {
            distribution: Distribution::Beckmann,
            ..Microfacet::ggx(alpha)
        }
    }

    /// A mirror: α below [`Microfacet::SMOOTH`].
    pub fn is_smooth(&self) -> bool {
        self.alpha < Self::SMOOTH
    }

    /// D(wm): the microfacet normal density, ∫ D(wm) cos θm dwm = 1 over
    /// the upper hemisphere (0 below it, and where it underflows).
    pub fn d(&self, wm: Vec3) -> f32 {
        let cos2 = wm.z * wm.z;
        if wm.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        let d = match self.distribution {
            Distribution::Ggx => {
                let e = 1.0 + tan2 / a2;
                1.0 / (PI * a2 * cos2 * cos2 * e * e)
            }
            Distribution::Beckmann => (-tan2 / a2).exp() / (PI * a2 * cos2 * cos2),
        };
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }

    /// a = 1 / (α tan θ) of direction `w` (∞ at normal incidence).
    fn a(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        let sin2 = (1.0 - cos2).max(0.0);
        if sin2 == 0.0 {
            return f32::INFINITY;
        }
        w.z.abs() / (self.alpha * sin2.sqrt())
    }

    /// GGX's Smith Λ(w) = (√(1 + α² tan²θ) − 1) / 2.
    fn lambda_ggx(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::INFINITY;
        }
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        0.5 * ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0)
    }

    /// G1(w), Mitsuba's `smith_g1` (without its facing test): exact for
    /// GGX, 1 / (1 + Λ) with Walter et al.'s fit for Beckmann.
    pub fn g1(&self, w: Vec3) -> f32 {
        match self.distribution {
            Distribution::Ggx => 1.0 / (1.0 + self.lambda_ggx(w)),
            Distribution::Beckmann => {
                if w.z == 0.0 {
                    return 0.0;
                }
                let a = self.a(w);
                if a >= 1.6 {
                    1.0
                } else {
                    (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
                }
            }
        }
    }

    /// G1(w) = 1 / (1 + Λ(w)) with Smith's exact Λ: for Beckmann
    /// Λ = (e^(−a²) / (a√π) − erfc(a)) / 2.
    pub fn g1_exact(&self, w: Vec3) -> f32 {
        match self.distribution {
            Distribution::Ggx => self.g1(w),
            Distribution::Beckmann => {
                if w.z == 0.0 {
                    return 0.0;
                }
                let a = self.a(w);
                if a > 9.0 {
                    return 1.0;
                }
                let lambda = 0.5 * ((-a * a).exp() / (a * PI.sqrt()) - erfc(a)).max(0.0);
                1.0 / (1.0 + lambda)
            }
        }
    }

    /// G(wo, wi) = G1(wo) G1(wi): separable masking–shadowing, Mitsuba 3's
    /// form (pbrt-v4 uses the height-correlated 1 / (1 + Λo + Λi)).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.g1(wo) * self.g1(wi)
    }

    /// Density of visible normals seen from `w` (mirrored to the upper side
    /// when below it, as the sampler does): G1(w) max(0, ±w·wm) D(wm) /
    /// |cos θ_w| with the exact G1.
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        let cos = w.z.abs();
        if cos == 0.0 {
            return 0.0;
        }
        let facing = (w.dot(wm) * w.z.signum()).max(0.0);
        self.g1_exact(w) / cos * self.d(wm) * facing
    }

    /// The solid-angle density of [`Microfacet::sample`] choosing `wm`
    /// seen from `w`.
    pub fn pdf(&self, w: Vec3, wm: Vec3) -> f32 {
        if self.sample_visible {
            self.d_visible(w, wm)
        } else {
            self.d(wm) * wm.z.max(0.0)
        }
    }

    /// A microfacet normal for the direction `w`, from two uniform numbers:
    /// visible from `w` (mirrored up first when below), or from D cos θm.
    pub fn sample(&self, w: Vec3, u: [f32; 2]) -> Vec3 {
        if !self.sample_visible {
            return self.sample_all(u);
        }
        match self.distribution {
            Distribution::Ggx => self.sample_visible_ggx(w, u),
            Distribution::Beckmann => self.sample_visible_beckmann(w, u),
        }
    }

    /// wm from D(wm) cos θm: φ uniform, tan²θ = α² u/(1 − u) (GGX) or
    /// −α² ln(1 − u) (Beckmann).
    fn sample_all(&self, u: [f32; 2]) -> Vec3 {
        let a2 = self.alpha * self.alpha;
        let tan2 = match self.distribution {
            Distribution::Ggx => a2 * u[0] / (1.0 - u[0]).max(1e-12),
            Distribution::Beckmann => -a2 * (1.0 - u[0]).max(1e-12).ln(),
        };
        let cos = 1.0 / (1.0 + tan2).sqrt();
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
    }

    /// Heitz 2018's GGX visible-normal sampler (a point on the projected
    /// hemisphere seen from the stretched direction).
    fn sample_visible_ggx(&self, w: Vec3, u: [f32; 2]) -> Vec3 {
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

    /// Beckmann visible normals (Heitz and d'Eon 2014): stretch `w` to
    /// α = 1, draw the slopes of the unit Beckmann surface seen from it,
    /// rotate and unstretch. The first slope's CDF,
    /// C(x) ∝ 1 + erf(x) + tan θ e^(−x²) / √π on x < cot θ, is inverted
    /// in v = erf(x) by Newton's method (from Jakob's starting guess, as
    /// Mitsuba does); the second slope is Gaussian.
    fn sample_visible_beckmann(&self, w: Vec3, u: [f32; 2]) -> Vec3 {
        let a = self.alpha;
        let mut ws = Vec3::new(a * w.x, a * w.y, w.z).normalize();
        if ws.z < 0.0 {
            ws = -ws;
        }
        let sin = (1.0 - ws.z * ws.z).max(0.0).sqrt();
        let (cos_phi, sin_phi) = if sin > 1e-7 {
            (ws.x / sin, ws.y / sin)
        } else {
            (1.0, 0.0)
        };
        let [sx, sy] = beckmann_slopes_11(ws.z, u);
        let slope_x = (cos_phi * sx - sin_phi * sy) * a;
        let slope_y = (sin_phi * sx + cos_phi * sy) * a;
        Vec3::new(-slope_x, -slope_y, 1.0).normalize()
    }
}

/// Slopes of the unit (α = 1) Beckmann surface visible from a direction at
/// cosine `cos_i` in the xz-plane.
fn beckmann_slopes_11(cos_i: f32, u: [f32; 2]) -> [f32; 2] {
    let u = u.map(|x| x.clamp(1e-6, 1.0 - 1e-6));
    let tan_i = (1.0 - cos_i * cos_i).max(0.0).sqrt() / cos_i;
    let cot_i = 1.0 / tan_i;
    let inv_sqrt_pi = 1.0 / PI.sqrt();
    let max_v = erf(cot_i);
    // The analytic inverse at grazing incidence, a good start everywhere.
    let mut v = max_v - (max_v + 1.0) * erf((-u[0].ln()).sqrt());
    let target = u[0] * (1.0 + max_v + inv_sqrt_pi * tan_i * (-cot_i * cot_i).exp());
    for _ in 0..4 {
        let x = erfinv(v);
        let value = 1.0 + v + inv_sqrt_pi * tan_i * (-x * x).exp() - target;
        let derivative = 1.0 - x * tan_i;
        v -= value / derivative;
        v = v.clamp(-1.0 + 1e-7, max_v);
    }
    [erfinv(v), erfinv(2.0 * u[1] - 1.0)]
}

#[cfg(test)]
mod microfacet_test {
    use super::*;
    use fogbank_math::Pcg32;

    fn all() -> Vec<Microfacet> {
        let mut v = Vec::new();
        for alpha in [0.05f32, 0.3, 0.8] {
            for m in [Microfacet::ggx(alpha), Microfacet::beckmann(alpha)] {
                v.push(m);
                v.push(Microfacet {
                    sample_visible: false,
                    ..m
                });
            }
        }
        v
    }

    /// ∫ D cos θm dwm = 1 and, for every view, ∫ D_visible dwm = 1 and
    /// ∫ pdf dwm = 1 (midpoint rule over the hemisphere).
    #[test]
    fn densities_normalise() {
        for m in all() {
            let n = 1200;
            let (mut proj, mut vis, mut pdf) = (0.0f64, 0.0f64, 0.0f64);
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
                    proj += m.d(wm) as f64 * c * dw;
                    vis += m.d_visible(w, wm) as f64 * dw;
                    pdf += m.pdf(w, wm) as f64 * dw;
                }
            }
            assert!((proj - 1.0).abs() < 2e-3, "{m:?}: ∫D cos = {proj}");
            assert!((vis - 1.0).abs() < 2e-3, "{m:?}: ∫D_vis = {vis}");
            assert!((pdf - 1.0).abs() < 2e-3, "{m:?}: ∫pdf = {pdf}");
        }
    }

    /// Mitsuba's rational G1 for Beckmann stays within 0.35 % of Smith's
    /// exact one, and GGX's two agree.
    #[test]
    fn beckmann_masking_fit_is_close_to_exact() {
        for m in [Microfacet::beckmann(0.4), Microfacet::ggx(0.4)] {
            for i in 1..200 {
                let c = i as f32 / 200.0;
                let w = Vec3::new((1.0 - c * c).sqrt(), 0.0, c);
                let (fit, exact) = (m.g1(w), m.g1_exact(w));
                assert!(
                    (fit - exact).abs() <= 0.0036 * exact + 1e-6,
                    "{m:?} cos {c}: {fit} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn sampled_normals_face_the_viewer() {
        let mut rng = Pcg32::new(1, 2);
        for m in all() {
            for _ in 0..10_000 {
                let w = Vec3::new(0.9, 0.1, 0.2).normalize();
                let wm = m.sample(w, [rng.next_f32(), rng.next_f32()]);
                assert!(
                    wm.z > 0.0 && (wm.length() - 1.0).abs() < 1e-5,
                    "{m:?}: {wm}"
                );
                if m.sample_visible {
                    assert!(w.dot(wm) >= -1e-4, "{m:?}: {wm} hidden from {w}");
                }
            }
        }
    }
}

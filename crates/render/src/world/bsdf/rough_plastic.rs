//! Rough plastic, as Mitsuba 3's `roughplastic`: a rough (GGX or Beckmann)
//! dielectric coating
//! over a Lambertian base. The coating reflects with the microfacet BRDF
//! F D G / (4 cos θi cos θo) tinted by `specular`; the base's light enters
//! and leaves through it, weighted by the rough coating's transmittance
//! T(θ) on both ways and divided by 1 − ρ F_int (or 1 − F_int) for the
//! light bouncing between base and coating:
//! f_d = ρ / (1 − F_int) · T(θi) T(θo) / (π η²). T(μ) = E_m[1 − F(wi·m)]
//! over the visible normals of a direction with cosine μ is tabulated at
//! construction on [`RES`] cosines and interpolated linearly; F_int is the
//! cosine-weighted hemispherical average of the inside reflectance
//! 1 − T_{1/η}. Lobes are chosen with Mitsuba's probabilities. One-sided.

use super::fresnel::{dielectric as fresnel, reflect, refract};
use super::microfacet::Microfacet;
use super::sample::{sample_cosine, BsdfSample};
use fogbank_math::special::gauss_legendre;
use glam::Vec3;
use std::collections::HashMap;
use std::f32::consts::PI;
use std::sync::{Mutex, OnceLock};

/// Cosines at which the coating's transmittance is tabulated (Mitsuba's
/// `MI_ROUGH_TRANSMITTANCE_RES`).
pub const RES: usize = 64;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughPlastic {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Interior over exterior IOR.
    pub eta: f32,
    pub mf: Microfacet,
    pub nonlinear: bool,
    coating: &'static Coating,
}

/// The coating's tables for one (distribution, α, η): computed once per
/// process (with visible-normal sampling, as Mitsuba's are) and
/// shared (leaked: a few hundred bytes per distinct coating), so that the
/// BSDF stays a small `Copy` value.
#[derive(Debug, PartialEq)]
struct Coating {
    /// T(μ) from outside at μ = max(10⁻⁶, i / (RES − 1)).
    external: [f32; RES],
    internal_reflectance: f32,
}

fn coating(mf: Microfacet, eta: f32) -> &'static Coating {
    type Cache = Mutex<HashMap<(bool, u32, u32), &'static Coating>>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    let beckmann = mf.distribution == super::microfacet::Distribution::Beckmann;
    let key = (beckmann, mf.alpha.to_bits(), eta.to_bits());
    if let Some(c) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return c;
    }
    let ggx = Microfacet {
        sample_visible: true,
        ..mf
    };
    let mu = |i: usize| (i as f32 / (RES - 1) as f32).max(1e-6);
    let external = std::array::from_fn(|i| transmittance(ggx, mu(i), eta));
    // 2 · mean of μ R(μ) over the table's cosines: Mitsuba's rule (a
    // plain mean, 1.2 % from the integral 2∫Rμ dμ at α = 0.25, which the
    // diffuse lobe's level depends on).
    let internal_reflectance = 2.0
        * (0..RES)
            .map(|i| mu(i) * internal_reflectance(ggx, mu(i), eta))
            .sum::<f32>()
        / RES as f32;
    let c: &'static Coating = Box::leak(Box::new(Coating {
        external,
        internal_reflectance,
    }));
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .entry(key)
        .or_insert(c)
}

fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) / 3.0
}

/// Σ over Gauss–Legendre points (`n` per axis) of the visible-normal
/// sampler's square of `f(m)` for the direction with cosine `mu`.
fn over_visible_normals(ggx: Microfacet, mu: f32, n: usize, f: impl Fn(Vec3, Vec3) -> f32) -> f32 {
    let w = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let q = gauss_legendre(n);
    let mut sum = 0.0f64;
    for &(x, wx) in &q {
        for &(y, wy) in &q {
            let m = ggx.sample(w, [x as f32, y as f32]);
            sum += wx * wy * f(w, m) as f64;
        }
    }
    sum as f32
}

/// G1 of `v` for microfacet `m` (0 when `m` faces away from `v`).
fn g1(ggx: Microfacet, v: Vec3, m: Vec3) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        0.0
    } else {
        ggx.g1(v)
    }
}

/// Light entering the coating at cosine `mu` (Mitsuba's
/// `eval_transmittance`): (1 − F) G1 of the refracted direction, over the
/// visible normals; 32 points per axis.
fn transmittance(ggx: Microfacet, mu: f32, eta: f32) -> f32 {
    over_visible_normals(ggx, mu, 32, |wi, m| match refract(wi, m, eta) {
        Some((wt, _)) if wt.z * wi.z < 0.0 => (1.0 - fresnel(wi.dot(m), eta)) * g1(ggx, wt, m),
        _ => 0.0,
    })
}

/// Light reflected back inside the coating at cosine `mu`: F(1/η) G1 of the
/// reflected direction; 128 points per axis.
fn internal_reflectance(ggx: Microfacet, mu: f32, eta: f32) -> f32 {
    over_visible_normals(ggx, mu, 128, |wi, m| {
        let wr = reflect(wi, m);
        if wr.z > 0.0 && wi.z > 0.0 {
            fresnel(wi.dot(m), 1.0 / eta) * g1(ggx, wr, m)
        } else {
            0.0
        }
    })
}

impl RoughPlastic {
    pub fn new(diffuse: Vec3, specular: Vec3, eta: f32, mf: Microfacet, nonlinear: bool) -> Self {
        RoughPlastic {
            diffuse,
            specular,
            eta,
            mf,
            nonlinear,
            coating: coating(mf, eta),
        }
    }

    /// The same coating over another base reflectance (a texture's value).
    /// The coating's tabulated transmittance over μ = cos θ (`RES` points
    /// on [0, 1]) and its internal diffuse reflectance: what a GPU port
    /// uploads instead of recomputing.
    pub fn coating(&self) -> (&[f32; RES], f32) {
        (&self.coating.external, self.coating.internal_reflectance)
    }

    pub fn with_diffuse(&self, diffuse: Vec3) -> Self {
        RoughPlastic { diffuse, ..*self }
    }

    /// T(μ), linearly interpolated.
    fn t(&self, mu: f32) -> f32 {
        let x = mu.clamp(0.0, 1.0) * (RES - 1) as f32;
        let i = (x as usize).min(RES - 2);
        let f = x - i as f32;
        self.coating.external[i] * (1.0 - f) + self.coating.external[i + 1] * f
    }

    fn specular_probability(&self, cos_o: f32) -> f32 {
        let (d, s) = (mean(self.diffuse), mean(self.specular));
        let w = s / (d + s);
        let t = self.t(cos_o);
        let ps = (1.0 - t) * w;
        let pd = t * (1.0 - w);
        ps / (ps + pd)
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let mf = self.mf;
        let h = (wo + wi).normalize();
        let g = g1(mf, wo, h) * g1(mf, wi, h);
        let spec = fresnel(wo.dot(h), self.eta) * mf.d(h) * g / (4.0 * wo.z * wi.z);
        let denom = if self.nonlinear {
            Vec3::ONE - self.diffuse * self.coating.internal_reflectance
        } else {
            Vec3::splat(1.0 - self.coating.internal_reflectance)
        };
        let diff =
            self.diffuse / denom * (self.t(wo.z) * self.t(wi.z) / (PI * self.eta * self.eta));
        self.specular * spec + diff
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        let ps = self.specular_probability(wo.z);
        // The normal's density over the Jacobian of reflection.
        let spec = self.mf.pdf(wo, h) / (4.0 * wo.dot(h));
        ps * spec + (1.0 - ps) * wi.z / PI
    }

    pub fn sample(&self, wo: Vec3, uc: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let ps = self.specular_probability(wo.z);
        let wi = if uc < ps {
            let m = self.mf.sample(wo, u);
            2.0 * wo.dot(m) * m - wo
        } else {
            sample_cosine(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            f: self.eval(wo, wi),
            pdf,
            delta: false,
        })
    }
}

#[cfg(test)]
mod rough_plastic_test {
    use super::*;

    /// A smooth-ish coating transmits 1 − F at normal incidence; at
    /// Mitsuba's values for GGX α = 0.25, η = 1.5 (its tables: t(1) =
    /// 0.955399, R_int = 0.45045) within their quadrature error.
    #[test]
    fn coating_tables_match_mitsuba() {
        let p = RoughPlastic::new(
            Vec3::splat(0.5),
            Vec3::ONE,
            1.5,
            Microfacet::ggx(0.01),
            false,
        );
        assert!(
            (p.t(1.0) - (1.0 - fresnel(1.0, 1.5))).abs() < 1e-3,
            "{}",
            p.t(1.0)
        );
        let p = RoughPlastic::new(
            Vec3::splat(0.5),
            Vec3::ONE,
            1.5,
            Microfacet::ggx(0.25),
            false,
        );
        assert!((p.t(1.0) - 0.955399).abs() < 2e-3, "{}", p.t(1.0));
        assert!(
            (p.coating.internal_reflectance - 0.45045).abs() < 2e-3,
            "{}",
            p.coating.internal_reflectance
        );
    }
}

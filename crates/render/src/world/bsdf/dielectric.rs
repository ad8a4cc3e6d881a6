//! Dielectrics (pbrt-v4 §9.5 and §9.7): a smooth interface reflects or
//! refracts with the Fresnel probabilities; a rough one does so about
//! microfacet normals (GGX or Beckmann), with the generalised half vector of refraction and
//! its Jacobian (Walter et al. 2007). Both sides scatter; `eta` is the
//! interior over the exterior IOR and the side is read from `wo.z`.
//! Refraction carries 1/η′² (radiance transport), η′ the IOR ratio crossed.
//! The thin dielectric sums the slab's inter-reflections (pbrt-v4 §9.5.3).

use super::fresnel::{dielectric as fresnel, reflect, refract};
use super::microfacet::Microfacet;
use super::sample::{same_hemisphere, BsdfSample};
use glam::Vec3;

/// The generalised half vector of (wo, wi) in the upper hemisphere and the
/// IOR ratio η′ crossed (1 for reflection), or None when it is undefined
/// or the configuration is a back-facing microfacet.
fn half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let (co, ci) = (wo.z, wi.z);
    if co == 0.0 || ci == 0.0 {
        return None;
    }
    let reflect = co * ci > 0.0;
    let etap = if reflect {
        1.0
    } else if co > 0.0 {
        eta
    } else {
        1.0 / eta
    };
    let wm = wi * etap + wo;
    if wm.length_squared() == 0.0 {
        return None;
    }
    let mut wm = wm.normalize();
    if wm.z < 0.0 {
        wm = -wm;
    }
    // Microfacets seen from behind by either direction contribute nothing.
    if wm.dot(wi) * ci < 0.0 || wm.dot(wo) * co < 0.0 {
        return None;
    }
    Some((wm, etap))
}

pub(super) fn eval(wo: Vec3, wi: Vec3, eta: f32, mf: Microfacet) -> f32 {
    if mf.is_smooth() || eta == 1.0 {
        return 0.0;
    }
    let Some((wm, etap)) = half_vector(wo, wi, eta) else {
        return 0.0;
    };
    let f = fresnel(wo.dot(wm), eta);
    if etap == 1.0 {
        return mf.d(wm) * mf.g(wo, wi) * f / (4.0 * wi.z * wo.z).abs();
    }
    let denom = wi.dot(wm) + wo.dot(wm) / etap;
    let denom = denom * denom * wi.z * wo.z;
    let ft = mf.d(wm) * (1.0 - f) * mf.g(wo, wi) * (wi.dot(wm) * wo.dot(wm) / denom).abs();
    ft / (etap * etap)
}

pub(super) fn pdf(wo: Vec3, wi: Vec3, eta: f32, mf: Microfacet) -> f32 {
    if mf.is_smooth() || eta == 1.0 {
        return 0.0;
    }
    let Some((wm, etap)) = half_vector(wo, wi, eta) else {
        return 0.0;
    };
    let r = fresnel(wo.dot(wm), eta);
    if etap == 1.0 {
        mf.pdf(wo, wm) / (4.0 * wo.dot(wm).abs()) * r
    } else {
        let denom = wi.dot(wm) + wo.dot(wm) / etap;
        let dwm_dwi = wi.dot(wm).abs() / (denom * denom);
        mf.pdf(wo, wm) * dwm_dwi * (1.0 - r)
    }
}

pub(super) fn sample(
    wo: Vec3,
    uc: f32,
    u: [f32; 2],
    eta: f32,
    mf: Microfacet,
) -> Option<BsdfSample> {
    if wo.z == 0.0 {
        return None;
    }
    if mf.is_smooth() || eta == 1.0 {
        return sample_smooth(wo, uc, eta);
    }
    let wm = mf.sample(wo, u);
    let r = fresnel(wo.dot(wm), eta);
    let wi = if uc < r {
        let wi = reflect(wo, wm);
        if !same_hemisphere(wo, wi) {
            return None;
        }
        wi
    } else {
        // refract() inverts η itself when wo is behind wm.
        let (wi, _) = refract(wo, wm, eta)?;
        if same_hemisphere(wo, wi) || wi.z == 0.0 {
            return None;
        }
        wi
    };
    let pdf = pdf(wo, wi, eta, mf);
    (pdf > 0.0).then(|| BsdfSample {
        wi,
        f: Vec3::splat(eval(wo, wi, eta, mf)),
        pdf,
        delta: false,
    })
}

fn sample_smooth(wo: Vec3, uc: f32, eta: f32) -> Option<BsdfSample> {
    let r = fresnel(wo.z, eta);
    if uc < r {
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        return Some(BsdfSample {
            wi,
            f: Vec3::splat(r / wi.z.abs()),
            pdf: r,
            delta: true,
        });
    }
    let (wi, etap) = refract(wo, Vec3::Z, eta)?;
    if wi.z == 0.0 {
        return None;
    }
    let t = 1.0 - r;
    Some(BsdfSample {
        wi,
        f: Vec3::splat(t / wi.z.abs() / (etap * etap)),
        pdf: t,
        delta: true,
    })
}

/// The fraction of light a thin slab passes straight through at incident
/// cosine `cos`: 1 − R′ with R′ = R + T²R / (1 − R²), the slab's
/// inter-reflections summed (what shadow rays see through it, Mitsuba's
/// `eval_null_transmission`).
pub(super) fn thin_transmission(cos: f32, eta: f32) -> f32 {
    let r = fresnel(cos.abs(), eta);
    if r < 1.0 {
        let t = 1.0 - r;
        1.0 - (r + t * t * r / (1.0 - r * r))
    } else {
        0.0
    }
}

pub(super) fn sample_thin(wo: Vec3, uc: f32, eta: f32) -> Option<BsdfSample> {
    if wo.z == 0.0 {
        return None;
    }
    let t = thin_transmission(wo.z, eta);
    let r = 1.0 - t;
    let (wi, p) = if uc < r {
        (Vec3::new(-wo.x, -wo.y, wo.z), r)
    } else {
        (-wo, t)
    };
    Some(BsdfSample {
        wi,
        f: Vec3::splat(p / wi.z.abs()),
        pdf: p,
        delta: true,
    })
}

//! Conductors: a mirror with the complex-IOR Fresnel term, or GGX
//! microfacets (Torrance–Sparrow with visible-normal sampling, pbrt-v4
//! §9.6.5). One-sided: below the surface they reflect nothing.

use super::fresnel::{conductor, reflect};
use super::microfacet::Ggx;
use super::sample::{same_hemisphere, BsdfSample};
use glam::Vec3;

pub(super) fn eval(wo: Vec3, wi: Vec3, eta: Vec3, k: Vec3, alpha: f32) -> Vec3 {
    if alpha < Ggx::SMOOTH || wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    let wm = wo + wi;
    if wm.length_squared() == 0.0 {
        return Vec3::ZERO;
    }
    let wm = wm.normalize();
    let ggx = Ggx { alpha };
    let f = conductor(wo.dot(wm).abs(), eta, k);
    ggx.d(wm) * ggx.g(wo, wi) * f / (4.0 * wo.z * wi.z)
}

pub(super) fn pdf(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    if alpha < Ggx::SMOOTH || wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let wm = wo + wi;
    if wm.length_squared() == 0.0 {
        return 0.0;
    }
    let wm = wm.normalize();
    Ggx { alpha }.d_visible(wo, wm) / (4.0 * wo.dot(wm).abs())
}

pub(super) fn sample(wo: Vec3, u: [f32; 2], eta: Vec3, k: Vec3, alpha: f32) -> Option<BsdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    if alpha < Ggx::SMOOTH {
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        return Some(BsdfSample {
            wi,
            f: conductor(wi.z, eta, k) / wi.z,
            pdf: 1.0,
            delta: true,
        });
    }
    let wm = Ggx { alpha }.sample_visible(wo, u);
    let wi = reflect(wo, wm);
    if !same_hemisphere(wo, wi) {
        return None;
    }
    let pdf = pdf(wo, wi, alpha);
    (pdf > 0.0).then(|| BsdfSample {
        wi,
        f: eval(wo, wi, eta, k, alpha),
        pdf,
        delta: false,
    })
}

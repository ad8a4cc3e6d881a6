//! Conductors: a mirror with the complex-IOR Fresnel term, or microfacets
//! (Torrance–Sparrow, pbrt-v4 §9.6.5, with GGX or Beckmann normals). One-
//! sided: below the surface they reflect nothing.

use super::fresnel::{conductor, reflect};
use super::microfacet::Microfacet;
use super::sample::{same_hemisphere, BsdfSample};
use glam::Vec3;

pub(super) fn eval(wo: Vec3, wi: Vec3, eta: Vec3, k: Vec3, mf: Microfacet) -> Vec3 {
    if mf.is_smooth() || wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    let wm = wo + wi;
    if wm.length_squared() == 0.0 {
        return Vec3::ZERO;
    }
    let wm = wm.normalize();
    let f = conductor(wo.dot(wm).abs(), eta, k);
    mf.d(wm) * mf.g(wo, wi) * f / (4.0 * wo.z * wi.z)
}

pub(super) fn pdf(wo: Vec3, wi: Vec3, mf: Microfacet) -> f32 {
    if mf.is_smooth() || wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let wm = wo + wi;
    if wm.length_squared() == 0.0 {
        return 0.0;
    }
    let wm = wm.normalize();
    mf.pdf(wo, wm) / (4.0 * wo.dot(wm).abs())
}

pub(super) fn sample(
    wo: Vec3,
    u: [f32; 2],
    eta: Vec3,
    k: Vec3,
    mf: Microfacet,
) -> Option<BsdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    if mf.is_smooth() {
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        return Some(BsdfSample {
            wi,
            f: conductor(wi.z, eta, k) / wi.z,
            pdf: 1.0,
            delta: true,
        });
    }
    let wm = mf.sample(wo, u);
    let wi = reflect(wo, wm);
    if !same_hemisphere(wo, wi) {
        return None;
    }
    let pdf = pdf(wo, wi, mf);
    (pdf > 0.0).then(|| BsdfSample {
        wi,
        f: eval(wo, wi, eta, k, mf),
        pdf,
        delta: false,
    })
}

//! The BSDF value type: one enum over the models, dispatched without
//! dynamic calls (see the module docs of `bsdf` for the table).

use super::microfacet::Microfacet;
use super::plastic::Plastic;
use super::rough_plastic::RoughPlastic;
use super::sample::{sample_cosine, BsdfSample};
use super::{conductor, dielectric};
use glam::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    Diffuse {
        reflectance: Vec3,
    },
    Conductor {
        eta: Vec3,
        k: Vec3,
        /// The rough surface's normals; a mirror when smooth
        /// ([`Microfacet::is_smooth`]).
        mf: Microfacet,
        /// Mitsuba's `specular_reflectance`, a tint on the Fresnel term.
        specular: Vec3,
    },
    Dielectric {
        /// Interior IOR over exterior IOR.
        eta: f32,
        mf: Microfacet,
    },
    ThinDielectric {
        eta: f32,
    },
    Plastic(Plastic),
    RoughPlastic(RoughPlastic),
    Null,
}

impl Bsdf {
    /// Every model's name, in the order of its id on the GPU (fogbank-gpu's
    /// contract writes them into the WGSL prelude as `BSDF_*`).
    pub const NAMES: [&'static str; 7] = [
        "diffuse",
        "conductor",
        "dielectric",
        "thin_dielectric",
        "plastic",
        "rough_plastic",
        "null",
    ];

    pub fn name(&self) -> &'static str {
        match self {
            Bsdf::Diffuse { .. } => "diffuse",
            Bsdf::Conductor { .. } => "conductor",
            Bsdf::Dielectric { .. } => "dielectric",
            Bsdf::ThinDielectric { .. } => "thin_dielectric",
            Bsdf::Plastic(_) => "plastic",
            Bsdf::RoughPlastic(_) => "rough_plastic",
            Bsdf::Null => "null",
        }
    }

    /// Whether every lobe is a delta (no `eval`, no MIS with light sampling).
    pub fn is_delta(&self) -> bool {
        match *self {
            Bsdf::Diffuse { .. } | Bsdf::Plastic(_) | Bsdf::RoughPlastic(_) => false,
            Bsdf::Conductor { mf, .. } | Bsdf::Dielectric { mf, .. } => mf.is_smooth(),
            Bsdf::ThinDielectric { .. } | Bsdf::Null => true,
        }
    }

    /// Whether some lobe is a delta (a smooth coat or interface, a pass
    /// through): light along it cannot be reached by light sampling.
    pub fn has_delta_lobe(&self) -> bool {
        match *self {
            Bsdf::Diffuse { .. } | Bsdf::RoughPlastic(_) => false,
            Bsdf::Plastic(_) | Bsdf::ThinDielectric { .. } | Bsdf::Null => true,
            Bsdf::Conductor { mf, .. } | Bsdf::Dielectric { mf, .. } => mf.is_smooth(),
        }
    }

    /// The fraction of light passing straight through at incident cosine
    /// `cos` when the surface lets light through unscattered in part
    /// (`null`: all; `thindielectric`: 1 − R′), else `None`: what shadow
    /// rays see, and why such passages are not path vertices.
    pub fn null_transmission(&self, cos: f32) -> Option<f32> {
        match *self {
            Bsdf::Null => Some(1.0),
            Bsdf::ThinDielectric { eta } => Some(dielectric::thin_transmission(cos, eta)),
            _ => None,
        }
    }

    /// f(wo, wi) (0 for delta lobes).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match *self {
            Bsdf::Diffuse { reflectance } => {
                if wo.z > 0.0 && wi.z > 0.0 {
                    reflectance / PI
                } else {
                    Vec3::ZERO
                }
            }
            Bsdf::Conductor {
                eta,
                k,
                mf,
                specular,
            } => conductor::eval(wo, wi, eta, k, mf) * specular,
            Bsdf::Dielectric { eta, mf } => Vec3::splat(dielectric::eval(wo, wi, eta, mf)),
            Bsdf::Plastic(p) => p.eval(wo, wi),
            Bsdf::RoughPlastic(p) => p.eval(wo, wi),
            Bsdf::ThinDielectric { .. } | Bsdf::Null => Vec3::ZERO,
        }
    }

    /// The solid-angle pdf of `sample` choosing `wi` (0 for delta lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match *self {
            Bsdf::Diffuse { .. } => {
                if wo.z > 0.0 && wi.z > 0.0 {
                    wi.z / PI
                } else {
                    0.0
                }
            }
            Bsdf::Conductor { mf, .. } => conductor::pdf(wo, wi, mf),
            Bsdf::Dielectric { eta, mf } => dielectric::pdf(wo, wi, eta, mf),
            Bsdf::Plastic(p) => p.pdf(wo, wi),
            Bsdf::RoughPlastic(p) => p.pdf(wo, wi),
            Bsdf::ThinDielectric { .. } | Bsdf::Null => 0.0,
        }
    }

    /// Samples `wi` from three uniform numbers (`uc` picks the lobe).
    pub fn sample(&self, wo: Vec3, uc: f32, u: [f32; 2]) -> Option<BsdfSample> {
        match *self {
            Bsdf::Diffuse { reflectance } => {
                if wo.z <= 0.0 {
                    return None;
                }
                let wi = sample_cosine(u);
                (wi.z > 0.0).then(|| BsdfSample {
                    wi,
                    f: reflectance / PI,
                    pdf: wi.z / PI,
                    delta: false,
                })
            }
            Bsdf::Conductor {
                eta,
                k,
                mf,
                specular,
            } => conductor::sample(wo, u, eta, k, mf).map(|mut s| {
                s.f *= specular;
                s
            }),
            Bsdf::Dielectric { eta, mf } => dielectric::sample(wo, uc, u, eta, mf),
            Bsdf::ThinDielectric { eta } => dielectric::sample_thin(wo, uc, eta),
            Bsdf::Plastic(p) => p.sample(wo, uc, u),
            Bsdf::RoughPlastic(p) => p.sample(wo, uc, u),
            Bsdf::Null => (wo.z != 0.0).then(|| BsdfSample {
                wi: -wo,
                f: Vec3::splat(1.0 / wo.z.abs()),
                pdf: 1.0,
                delta: true,
            }),
        }
    }
}

//! Surface scattering: BSDFs in the local shading frame (z along the
//! shading normal), in pbrt-v4's conventions — `wo` and `wi` both point
//! away from the surface, `wo` towards where the path came from — and
//! Mitsuba 3's plugin names and parameters. Values are radiance-transport
//! BSDF values f(wo, wi) (transmission through an IOR change carries
//! 1/η², pbrt-v4 §9.5.2); `pdf` is in solid angle of `wi`; delta lobes
//! (smooth surfaces) have `eval` and `pdf` 0 and are reached only by
//! `sample`, which reports them.
//!
//! | variant | Mitsuba plugin | lobes |
//! |---|---|---|
//! | `Diffuse` | `diffuse` | Lambertian reflection, one-sided |
//! | `Conductor` | `conductor`, `roughconductor` | Fresnel of complex IOR, smooth (α < [`microfacet::Microfacet::SMOOTH`]) or rough (GGX or Beckmann, [`microfacet`]), one-sided |
//! | `Dielectric` | `dielectric`, `roughdielectric` | reflection + refraction, smooth or rough, both sides |
//! | `ThinDielectric` | `thindielectric` | mirror reflection + straight transmission through a thin slab |
//! | `Plastic` | `plastic` | smooth coating (delta) over a Lambertian base with internal scattering, one-sided |
//! | `RoughPlastic` | `roughplastic` | rough coating over a Lambertian base, the coating's transmittance tabulated, one-sided |
//! | `Null` | `null` | straight through (index-matched medium boundaries) |
//!
//! [`TwoSided`] wraps one-sided models as Mitsuba's `twosided` does.

pub mod fresnel;
pub mod microfacet;

mod conductor;
mod dielectric;
mod model;
mod plastic;
mod rough_plastic;
mod sample;
mod two_sided;

pub use microfacet::{Distribution, Microfacet};
pub use model::Bsdf;
pub use plastic::{diffuse_fresnel, Plastic};
pub use rough_plastic::RoughPlastic;
pub use sample::{sample_cosine, BsdfSample};
pub use two_sided::TwoSided;

//! A shape's `bsdf` table: Mitsuba 3's BSDF plugins with their parameter
//! names and defaults, and what the integrators evaluate at a hit point
//! (the BSDF with its textures looked up at the hit's UV).
//!
//! | `type` | keys (default) |
//! |---|---|
//! | `diffuse` | `reflectance` (0.5) |
//! | `conductor` | `eta` (0), `k` (1), `specular_reflectance` (1): the defaults are Mitsuba's `material = "none"`, a perfect mirror; or `material` (`"Au"`, `"Cu"`, `"Al"`, … any of Mitsuba's, [`super::conductors`]) instead of `eta` and `k` |
//! | `roughconductor` | as `conductor`, plus `alpha` (0.1), `distribution` (`"beckmann"` or `"ggx"`; `"beckmann"`, Mitsuba 3's default — pbrt-v4 scenes read as `"ggx"`, its only one), `sample_visible` (true) |
//! | `dielectric` | `int_ior` (`bk7`), `ext_ior` (`air`) |
//! | `roughdielectric` | as `dielectric`, plus `alpha`, `distribution`, `sample_visible` as `roughconductor` |
//! | `thindielectric` | `int_ior` (`bk7`), `ext_ior` (`air`) |
//! | `plastic` | `diffuse_reflectance` (0.5), `specular_reflectance` (1), `int_ior` (`polypropylene`), `ext_ior` (`air`), `nonlinear` (false) |
//! | `roughplastic` | as `plastic`, plus `alpha`, `distribution`, `sample_visible` as `roughconductor` |
//! | `null` | — (an index-matched boundary: rays pass straight through) |
//! | `twosided` | `bsdf` (one table for both sides) or `front` and `back` |
//!
//! A reflectance is a grey number, an RGB triple or a texture table
//! (`{ type = "checkerboard", color0 = 0.4, color1 = 0.2, to_uv = { scale = [4, 4] } }`,
//! `{ type = "bitmap", filename = "wood.png", filter_type = "bilinear",
//! wrap_mode = "repeat", raw = false, to_uv = … }`, the file relative to the
//! scene file; see `world::bitmap`).
//! IORs are numbers or the names of Mitsuba's table ([`super::ior::IOR_TABLE`]). The
//! rough models' normals follow [`crate::world::bsdf::Microfacet`]; the
//! default distribution is Mitsuba's, Beckmann, as the models and their
//! other keys are Mitsuba's (the pbrt-v4 reader writes GGX, pbrt's only one).

use super::ior::{ior, IorDesc};
use super::spectrum::SpectrumDesc;
use crate::error::SceneError;
use crate::world::bsdf::Distribution;
use serde::{Deserialize, Serialize};

fn grey(v: f32) -> SpectrumDesc {
    SpectrumDesc::Grey(v)
}
fn half() -> SpectrumDesc {
    grey(0.5)
}
fn one() -> SpectrumDesc {
    grey(1.0)
}
fn rough() -> f32 {
    0.1
}
fn beckmann() -> String {
    "beckmann".into()
}
fn is_beckmann(s: &String) -> bool {
    s == "beckmann"
}
fn yes() -> bool {
    true
}
fn is_true(b: &bool) -> bool {
    *b
}
fn bk7() -> IorDesc {
    ior("bk7")
}
fn air() -> IorDesc {
    ior("air")
}
fn polypropylene() -> IorDesc {
    ior("polypropylene")
}

/// A rough model's `distribution` key.
pub(super) fn distribution_of(name: &str, key: &str) -> Result<Distribution, SceneError> {
    match name {
        "ggx" => Ok(Distribution::Ggx),
        "beckmann" => Ok(Distribution::Beckmann),
        other => Err(SceneError(format!(
            "{key}: `{other}` is not ggx or beckmann"
        ))),
    }
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum BsdfDesc {
    Diffuse {
        #[serde(default = "half")]
        reflectance: SpectrumDesc,
    },
    Conductor {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        eta: Option<[f32; 3]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        k: Option<[f32; 3]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        material: Option<String>,
        #[serde(default = "one")]
        specular_reflectance: SpectrumDesc,
    },
    Roughconductor {
        #[serde(default = "rough")]
        alpha: f32,
        #[serde(default = "beckmann", skip_serializing_if = "is_beckmann")]
        distribution: String,
        #[serde(default = "yes", skip_serializing_if = "is_true")]
        sample_visible: bool,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        eta: Option<[f32; 3]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        k: Option<[f32; 3]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        material: Option<String>,
        #[serde(default = "one")]
        specular_reflectance: SpectrumDesc,
    },
    Dielectric {
        #[serde(default = "bk7")]
        int_ior: IorDesc,
        #[serde(default = "air")]
        ext_ior: IorDesc,
    },
    Roughdielectric {
        #[serde(default = "rough")]
        alpha: f32,
        #[serde(default = "beckmann", skip_serializing_if = "is_beckmann")]
        distribution: String,
        #[serde(default = "yes", skip_serializing_if = "is_true")]
        sample_visible: bool,
        #[serde(default = "bk7")]
        int_ior: IorDesc,
        #[serde(default = "air")]
        ext_ior: IorDesc,
    },
    Thindielectric {
        #[serde(default = "bk7")]
        int_ior: IorDesc,
        #[serde(default = "air")]
        ext_ior: IorDesc,
    },
    Plastic {
        #[serde(default = "half")]
        diffuse_reflectance: SpectrumDesc,
        #[serde(default = "one")]
        specular_reflectance: SpectrumDesc,
        #[serde(default = "polypropylene")]
        int_ior: IorDesc,
        #[serde(default = "air")]
        ext_ior: IorDesc,
        #[serde(default)]
        nonlinear: bool,
    },
    Roughplastic {
        #[serde(default = "rough")]
        alpha: f32,
        #[serde(default = "beckmann", skip_serializing_if = "is_beckmann")]
        distribution: String,
        #[serde(default = "yes", skip_serializing_if = "is_true")]
        sample_visible: bool,
        #[serde(default = "half")]
        diffuse_reflectance: SpectrumDesc,
        #[serde(default = "one")]
        specular_reflectance: SpectrumDesc,
        #[serde(default = "polypropylene")]
        int_ior: IorDesc,
        #[serde(default = "air")]
        ext_ior: IorDesc,
        #[serde(default)]
        nonlinear: bool,
    },
    Null,
    Twosided {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bsdf: Option<Box<BsdfDesc>>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        front: Option<Box<BsdfDesc>>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        back: Option<Box<BsdfDesc>>,
    },
}

impl Default for BsdfDesc {
    /// Mitsuba's default for a shape without a BSDF: grey diffuse.
    fn default() -> Self {
        BsdfDesc::Diffuse {
            reflectance: half(),
        }
    }
}

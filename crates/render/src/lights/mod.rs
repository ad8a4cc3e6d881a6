//! Light sources: their scene description and the built lights.

pub mod area;
pub mod bvh;
pub mod disk;
pub mod envmap;
pub mod light_bounds;
pub mod sample;
pub mod sky;
pub mod sphere;

use crate::error::SceneError;
use fogbank_math::Vec3;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// | type | keys |
/// |---|---|
/// | `constant` | `radiance` (RGB) |
/// | `envmap` | `file`, `scale` (1), `rotate`, `filter` (`nearest`; `bilinear` is Mitsuba 3's lookup) |
/// | `point` | `position`, `intensity` (RGB) |
/// | `directional` | `direction` (towards which light travels), `irradiance` (RGB) |
/// | `spot` | `position`, `direction`, `intensity` (RGB), `cone_angle` (30°), `falloff_start` (25°), `curve` (`smoothstep`: pbrt-v4's; `linear`: Mitsuba 3's, linear in the angle) |
/// | `sky` | `zenith`, `horizon`, `ground` (RGB), `scale` (1): a procedural gradient sky, rendered as an environment map |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LightDesc {
    Constant {
        radiance: [f32; 3],
    },
    Envmap {
        file: String,
        #[serde(default = "one")]
        scale: f32,
        /// Rotation as `[x, y, z, degrees]` (axis and angle).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rotate: Option<[f32; 4]>,
        /// `nearest` (default: exact importance sampling) or `bilinear`
        /// (Mitsuba 3's lookup; the XML reader sets it).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        filter: Option<String>,
    },
    Point {
        position: [f32; 3],
        intensity: [f32; 3],
    },
    Directional {
        direction: [f32; 3],
        irradiance: [f32; 3],
    },
    /// A procedural gradient sky (see [`sky`]); built as an environment map.
    Sky {
        zenith: [f32; 3],
        horizon: [f32; 3],
        ground: [f32; 3],
        #[serde(default = "one")]
        scale: f32,
    },
    /// A point light emitting into a cone around `direction`: full intensity
    /// within `falloff_start` degrees of the axis, down to zero at
    /// `cone_angle` degrees along `curve`.
    Spot {
        position: [f32; 3],
        direction: [f32; 3],
        intensity: [f32; 3],
        #[serde(default = "default_cone")]
        cone_angle: f32,
        #[serde(default = "default_falloff")]
        falloff_start: f32,
        #[serde(default, skip_serializing_if = "SpotCurve::is_smoothstep")]
        curve: SpotCurve,
    },
}

/// How a spotlight's intensity falls from the inner cone to the outer one.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SpotCurve {
    /// Smoothstep in cos θ (pbrt-v4's `spot`).
    #[default]
    Smoothstep = 0,
    /// Linear in the angle θ (Mitsuba 3's `spot`, which the XML reader
    /// gives).
    Linear = 1,
}

impl SpotCurve {
    fn is_smoothstep(&self) -> bool {
        *self == SpotCurve::Smoothstep
    }
}

fn default_cone() -> f32 {
    30.0
}
fn default_falloff() -> f32 {
    25.0
}

fn one() -> f32 {
    1.0
}

#[derive(Clone, Debug)]
pub enum Light {
    Constant {
        radiance: Vec3,
    },
    Envmap(std::sync::Arc<envmap::Envmap>),
    Point {
        position: Vec3,
        intensity: Vec3,
    },
    Directional {
        direction: Vec3,
        irradiance: Vec3,
    },
    /// Cosines of the falloff start and of the cone edge.
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cos_falloff_start: f32,
        cos_total: f32,
        curve: SpotCurve,
    },
    /// One triangle of an emitting shape (built from `[[shapes]]`, not
    /// `[[lights]]`).
    Area(area::AreaTriangle),
    /// An emitting analytic sphere or disk (from `[[shapes]]`).
    Sphere(sphere::SphereLight),
    Disk(disk::DiskLight),
}

impl Light {
    /// Every kind of light, by the name its `type` has in a scene
    /// (`area`, `sphere` and `disk` lights come from shapes' emitters and
    /// are not listed).
    pub const KINDS: [&'static str; 5] = ["constant", "envmap", "point", "directional", "spot"];

    pub fn kind(&self) -> &'static str {
        match self {
            Light::Constant { .. } => "constant",
            Light::Envmap(_) => "envmap",
            Light::Point { .. } => "point",
            Light::Directional { .. } => "directional",
            Light::Spot { .. } => "spot",
            Light::Area(_) => "area",
            Light::Sphere(_) => "sphere",
            Light::Disk(_) => "disk",
        }
    }

    /// Whether the light is an emitting shape's (these follow the scene's
    /// `[[lights]]` in `World::lights`).
    pub fn is_shape(&self) -> bool {
        matches!(self, Light::Area(_) | Light::Sphere(_) | Light::Disk(_))
    }
}

impl LightDesc {
    /// The light `lights.{i}`, files resolved against `base`.
    pub fn build(&self, i: usize, base: &Path) -> Result<Light, SceneError> {
        let l = self;
        Ok(match l {
            LightDesc::Constant { radiance } => Light::Constant {
                radiance: Vec3::from(*radiance),
            },
            LightDesc::Envmap {
                file,
                scale,
                rotate,
                filter,
            } => Light::Envmap(std::sync::Arc::new(load_envmap(
                &base.join(file),
                *scale,
                *rotate,
                filter.as_deref(),
                i,
            )?)),
            LightDesc::Sky {
                zenith,
                horizon,
                ground,
                scale,
            } => {
                let env = sky::sky_envmap(*zenith, *horizon, *ground, *scale)
                    .map_err(|e| SceneError(format!("lights.{i} (sky): {e}")))?;
                Light::Envmap(std::sync::Arc::new(env))
            }
            LightDesc::Point {
                position,
                intensity,
            } => Light::Point {
                position: Vec3::from(*position),
                intensity: Vec3::from(*intensity),
            },
            LightDesc::Directional {
                direction,
                irradiance,
            } => Light::Directional {
                direction: Vec3::from(*direction)
                    .try_normalize()
                    .ok_or_else(|| SceneError(format!("lights.{i}.direction: zero vector")))?,
                irradiance: Vec3::from(*irradiance),
            },
            LightDesc::Spot {
                position,
                direction,
                intensity,
                cone_angle,
                falloff_start,
                curve,
            } => {
                if !(*cone_angle > 0.0
                    && *cone_angle <= 180.0
                    && *falloff_start >= 0.0
                    && falloff_start <= cone_angle)
                {
                    return Err(SceneError(format!(
                        "lights.{i}: need 0 ≤ falloff_start ≤ cone_angle ≤ 180 degrees, cone_angle > 0"
                    )));
                }
                Light::Spot {
                    position: Vec3::from(*position),
                    direction: Vec3::from(*direction)
                        .try_normalize()
                        .ok_or_else(|| SceneError(format!("lights.{i}.direction: zero vector")))?,
                    intensity: Vec3::from(*intensity),
                    cos_falloff_start: falloff_start.to_radians().cos(),
                    cos_total: cone_angle.to_radians().cos(),
                    curve: *curve,
                }
            }
        })
    }
}

/// The environment map `path` of light `lights.{i}`, scaled, rotated by
/// `rotate` (axis and degrees) and filtered as asked.
fn load_envmap(
    path: &Path,
    scale: f32,
    rotate: Option<[f32; 4]>,
    filter: Option<&str>,
    i: usize,
) -> Result<envmap::Envmap, SceneError> {
    let rotation = match rotate {
        Some([x, y, z, deg]) => glam::Mat3::from_axis_angle(
            Vec3::new(x, y, z)
                .try_normalize()
                .ok_or_else(|| SceneError(format!("lights.{i}.rotate: zero axis")))?,
            deg.to_radians(),
        ),
        None => glam::Mat3::IDENTITY,
    };
    let mut env = envmap::Envmap::load(path, scale, rotation)
        .map_err(|e| SceneError(format!("lights.{i}: {e}")))?;
    match filter {
        None | Some("nearest") => {}
        Some("bilinear") => env = env.bilinear(),
        Some(other) => {
            return Err(SceneError(format!(
                "lights.{i}.filter: `{other}` is not nearest or bilinear"
            )))
        }
    }
    Ok(env)
}

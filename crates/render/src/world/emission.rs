//! Volumetric emission L_e of a medium (see `EmissionDesc` for the keys).

use super::blackbody::blackbody_rgb;
use super::field::{Field, FieldDesc};
use crate::error::SceneError;
use fogbank_math::{DAffine3, Vec3};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Emitted radiance L_e of a medium. Following pbrt-v4, a medium emits
/// where it absorbs: the radiance gained along a ray is ∫ T σ_a L_e dt with
/// σ_a = σ_t (1 − albedo), so emission needs albedo < 1 and vanishes where
/// the density does.
///
/// | key | default | meaning |
/// |---|---|---|
/// | `color` | (1, 1, 1) | RGB radiance (or tint of the blackbody) |
/// | `scale` | 1 | multiplies the radiance |
/// | `grid` | none | a grid (same keys as `density`) multiplying `color` |
/// | `temperature` | none | a temperature grid in kelvin: L_e = scale · color · blackbody(T), the Planck spectrum normalised to peak 1 (as pbrt-v4) in linear sRGB |
/// | `temperature_scale`, `temperature_offset` | 1, 0 | T = (grid − offset) · scale; T ≤ 100 K emits nothing |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EmissionDesc {
    #[serde(default = "white")]
    pub color: [f32; 3],
    #[serde(default = "one")]
    pub scale: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<FieldDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature: Option<FieldDesc>,
    #[serde(default = "one")]
    pub temperature_scale: f32,
    #[serde(default)]
    pub temperature_offset: f32,
}

fn white() -> [f32; 3] {
    [1.0; 3]
}

fn one() -> f32 {
    1.0
}

#[derive(Clone, Debug)]
pub enum Emission {
    /// L_e = radiance (times a grid when present).
    Color { radiance: Vec3, grid: Option<Field> },
    /// L_e = radiance · blackbody((grid − offset) · scale).
    Blackbody {
        radiance: Vec3,
        temperature: Field,
        scale: f32,
        offset: f32,
    },
}

impl Emission {
    pub fn build(
        d: &EmissionDesc,
        key: &str,
        base: &Path,
        to_world: DAffine3,
    ) -> Result<Emission, SceneError> {
        let radiance = Vec3::from(d.color) * d.scale;
        if !(radiance.is_finite() && radiance.min_element() >= 0.0) {
            return Err(SceneError(format!(
                "{key}: color · scale must be finite and ≥ 0"
            )));
        }
        if !(d.temperature_scale.is_finite() && d.temperature_offset.is_finite()) {
            return Err(SceneError(format!(
                "{key}: temperature_scale and temperature_offset must be finite"
            )));
        }
        match (&d.grid, &d.temperature) {
            (Some(_), Some(_)) => Err(SceneError(format!(
                "{key}: give `grid` or `temperature`, not both"
            ))),
            (None, Some(t)) => Ok(Emission::Blackbody {
                radiance,
                temperature: Field::load(t, &format!("{key}.temperature"), base, to_world)?,
                scale: d.temperature_scale,
                offset: d.temperature_offset,
            }),
            (g, None) => Ok(Emission::Color {
                radiance,
                grid: g
                    .as_ref()
                    .map(|g| Field::load(g, &format!("{key}.grid"), base, to_world))
                    .transpose()?,
            }),
        }
    }

    /// L_e at world point `p`.
    pub fn radiance(&self, p: Vec3) -> Vec3 {
        match self {
            Emission::Color { radiance, grid } => match grid {
                Some(g) => *radiance * g.eval(p).max(Vec3::ZERO),
                None => *radiance,
            },
            Emission::Blackbody {
                radiance,
                temperature,
                scale,
                offset,
            } => *radiance * blackbody_rgb((temperature.eval(p).x - offset) * scale),
        }
    }
}

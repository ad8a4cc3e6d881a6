//! Volumetric emission L_e of a medium (see `EmissionDesc` for the keys).

use crate::blackbody::blackbody_rgb;
use crate::desc::{EmissionDesc, SceneError};
use crate::field::Field;
use fogbank_math::{DAffine3, Vec3};
use std::path::Path;

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

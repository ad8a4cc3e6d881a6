//! `<emitter>` elements as `[[lights]]` tables (`area` emitters belong to
//! their shapes, see `shapes`).

use super::bsdfs::rgb_value;
use super::plugin::{Ids, Plugin};
use super::xml::{Document, Element};
use fogbank_image::spectrum::SpectrumUse;
use fogbank_render::error::SceneError;
use glam::{DMat3, DQuat, DVec3};
use toml::{Table, Value};

fn vec3(v: DVec3) -> Value {
    Value::Array(v.to_array().iter().map(|&x| Value::Float(x)).collect())
}

pub fn light(e: &Element, ids: &Ids, doc: &Document) -> Result<Table, SceneError> {
    let p = Plugin::new(e, ids)?;
    let mut t = Table::new();
    // Mitsuba's emitters default to 1 (radiance, intensity, irradiance).
    let rgb = |name: &str| -> Result<[f32; 3], SceneError> {
        Ok(p.rgb(name, SpectrumUse::Emitter)?.unwrap_or([1.0; 3]))
    };
    let to_world = p.transform("to_world")?;
    match p.ty {
        "constant" => {
            t.insert("type".into(), "constant".into());
            t.insert("radiance".into(), rgb_value(rgb("radiance")?));
        }
        "envmap" => {
            let path = p.filename(doc)?;
            t.insert("type".into(), "envmap".into());
            t.insert("file".into(), path.display().to_string().into());
            t.insert("filter".into(), "bilinear".into());
            if let Some(s) = p.float("scale")? {
                t.insert("scale".into(), s.into());
            }
            if let Some(m) = to_world {
                t.insert("rotate".into(), envmap_rotation(&p, m)?);
            }
        }
        "point" => {
            let pos = match (p.vector("position")?, to_world) {
                (Some(v), None) => DVec3::from(v),
                (None, Some(m)) => m.transform_point3(DVec3::ZERO),
                (None, None) => DVec3::ZERO,
                (Some(_), Some(_)) => {
                    return Err(p.error("give `position` or `to_world`, not both"))
                }
            };
            t.insert("type".into(), "point".into());
            t.insert("position".into(), vec3(pos));
            t.insert("intensity".into(), rgb_value(rgb("intensity")?));
        }
        "directional" => {
            let dir = match (p.vector("direction")?, to_world) {
                (Some(v), None) => DVec3::from(v),
                (None, Some(m)) => m.transform_vector3(DVec3::Z),
                (None, None) => DVec3::Z,
                (Some(_), Some(_)) => {
                    return Err(p.error("give `direction` or `to_world`, not both"))
                }
            };
            t.insert("type".into(), "directional".into());
            t.insert("direction".into(), vec3(dir));
            t.insert("irradiance".into(), rgb_value(rgb("irradiance")?));
        }
        "spot" => spot(&p, to_world, &mut t)?,
        "area" => return Err(p.error("an area emitter belongs inside a <shape>")),
        other => {
            return Err(p.error(format!(
                "emitter `{other}` is not supported (constant, envmap, point, directional, spot; \
                 area in shapes)"
            )))
        }
    }
    p.finish()?;
    Ok(t)
}

/// An envmap's `to_world`, which must be a rotation, as `rotate` (axis and
/// degrees).
fn envmap_rotation(p: &Plugin, m: glam::DMat4) -> Result<Value, SceneError> {
    let r = DMat3::from_mat4(m);
    if !(r.transpose() * r).abs_diff_eq(DMat3::IDENTITY, 1e-5) || r.determinant() < 0.0 {
        return Err(p.error("an envmap's to_world must be a rotation"));
    }
    let (axis, angle) = DQuat::from_mat3(&r).to_axis_angle();
    let mut rot = axis.to_array().to_vec();
    rot.push(angle.to_degrees());
    Ok(Value::Array(rot.into_iter().map(Value::Float).collect()))
}

/// A `spot` emitter's keys.
fn spot(p: &Plugin, to_world: Option<glam::DMat4>, t: &mut Table) -> Result<(), SceneError> {
    // Mitsuba's spot sits at the origin of its to_world and shines
    // along its +z axis, linear in the angle from `beam_width` to
    // `cutoff_angle` (degrees).
    let m = to_world.unwrap_or(glam::DMat4::IDENTITY);
    let cutoff = p.float("cutoff_angle")?.unwrap_or(20.0);
    let beam = p.float("beam_width")?.unwrap_or(cutoff * 0.75);
    if !(cutoff > 0.0 && cutoff <= 180.0 && beam >= 0.0 && beam <= cutoff) {
        return Err(p.error("needs 0 ≤ beam_width ≤ cutoff_angle ≤ 180, cutoff_angle > 0"));
    }
    t.insert("type".into(), "spot".into());
    t.insert("position".into(), vec3(m.transform_point3(DVec3::ZERO)));
    t.insert("direction".into(), vec3(m.transform_vector3(DVec3::Z)));
    let intensity = p
        .rgb("intensity", SpectrumUse::Emitter)?
        .unwrap_or([1.0; 3]);
    t.insert("intensity".into(), rgb_value(intensity));
    t.insert("cone_angle".into(), cutoff.into());
    t.insert("falloff_start".into(), beam.into());
    t.insert("curve".into(), "linear".into());
    Ok(())
}

/// A shape's `area` emitter: `{ radiance }`.
pub fn area(e: &Element, ids: &Ids) -> Result<Table, SceneError> {
    let p = Plugin::new(e, ids)?;
    if p.ty != "area" {
        return Err(p.error("a shape's emitter must be `area`"));
    }
    let r = p.rgb("radiance", SpectrumUse::Emitter)?.unwrap_or([1.0; 3]);
    p.finish()?;
    let mut t = Table::new();
    t.insert("radiance".into(), rgb_value(r));
    Ok(t)
}

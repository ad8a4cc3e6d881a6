//! `LightSource` and `AreaLightSource` as `[[lights]]` tables and shape
//! emitters, with pbrt-v4's `scale`, `power` and `illuminance`.
//!
//! | pbrt | fogbank | radiometry |
//! |---|---|---|
//! | `point` I, from | `point` `intensity`, `position` | I·scale; `power` P: ·P/(4π) |
//! | `spot` I, from, to, coneangle (30), conedeltaangle (5) | `spot` with pbrt's smoothstep falloff from coneangle − conedeltaangle | I·scale; `power` P: ·P/(2π(1 − cos θ_start + (cos θ_start − cos θ_end)/2)) |
//! | `distant` L, from (0,0,0), to (0,0,1) | `directional` `irradiance` along to − from | L·scale; `illuminance` E: ·E |
//! | `infinite` L | `constant` `radiance` | L·scale; `illuminance` E: ·E/π |
//! | `infinite` filename | `envmap` of the map resampled to lat-long ([`super::envlight`]) | scale; `illuminance` E: ·E/(pbrt's estimate of the map's) |
//! | area `diffuse` L | shape `emitter.radiance` | L·scale; `power` P: ·P/(π·area) (spheres and disks, whose area is known) |
//!
//! Spectra follow [`super::spectra`] (an rgb is its own luminance, other
//! spectra are normalised to luminance 1); a light without its spectrum
//! gets the colour space's illuminant, white (1, 1, 1) in linear sRGB.
//! A light's medium (pbrt's outside medium at the statement) needs no
//! mapping: fogbank's media are regions, and a light is in those that hold
//! it. Refused: `portal` infinite lights, `goniometric`, `projection`, two-sided area
//! lights.

use super::interpret::Placed;
use super::params::ParamList;
use super::spectra::{spectrum, Role};
use super::warnings::Warnings;
use fogbank_render::error::SceneError;
use glam::{DMat4, DVec3};
use std::f64::consts::PI;
use std::path::Path;
use toml::{Table, Value};

fn vec3(v: DVec3) -> Value {
    Value::Array(v.to_array().iter().map(|&x| Value::Float(x)).collect())
}

fn rgb_value(c: [f64; 3]) -> Value {
    Value::Array(c.iter().map(|&x| Value::Float(x)).collect())
}

fn point_param(ps: &ParamList, name: &str, default: DVec3) -> Result<DVec3, SceneError> {
    Ok(ps.vec3(name)?.map(DVec3::from).unwrap_or(default))
}

/// The emitted spectrum `name` times `scale` and `extra` (what `power` or
/// `illuminance` ask for; `None` when not given).
fn emitted(ps: &ParamList, name: &str, extra: f64) -> Result<[f64; 3], SceneError> {
    let c = spectrum(ps, name, Role::Illuminant)?.unwrap_or([1.0; 3]);
    let s = ps.float("scale", 1.0)? * extra;
    Ok(c.map(|x| x * s))
}

/// A positive `power`/`illuminance` parameter, if given.
fn positive(ps: &ParamList, name: &str) -> Result<Option<f64>, SceneError> {
    Ok(ps.one("float", name)?.filter(|&x| x > 0.0))
}

/// A `LightSource` (file names resolve against `top_dir`).
pub fn light(l: &Placed, top_dir: &Path, warnings: &mut Warnings) -> Result<Table, SceneError> {
    let e = &l.entity;
    let ps = &e.params;
    let m: DMat4 = l.ctm;
    let mut t = Table::new();
    let what = e.what("LightSource");
    let err = |msg: String| e.loc.error(format!("{what}: {msg}"));
    match e.ty.as_str() {
        "point" => {
            let k = positive(ps, "power")?.map(|p| p / (4.0 * PI)).unwrap_or(1.0);
            t.insert("type".into(), "point".into());
            t.insert("intensity".into(), rgb_value(emitted(ps, "I", k)?));
            let from = point_param(ps, "from", DVec3::ZERO)?;
            t.insert("position".into(), vec3(m.transform_point3(from)));
        }
        "spot" => spot(ps, m, &mut t).map_err(|x| err(x.0))?,
        "distant" => {
            let k = positive(ps, "illuminance")?.unwrap_or(1.0);
            let from = point_param(ps, "from", DVec3::ZERO)?;
            let to = point_param(ps, "to", DVec3::Z)?;
            let d = m.transform_vector3(to - from).try_normalize().ok_or_else(|| err("from = to".into()))?;
            t.insert("type".into(), "directional".into());
            t.insert("direction".into(), vec3(d));
            t.insert("irradiance".into(), rgb_value(emitted(ps, "L", k)?));
        }
        "infinite" if ps.has("portal") => {
            return Err(err("portal infinite lights are not supported".into()))
        }
        "infinite" if ps.has("filename") => t = super::envlight::image_light(l, top_dir, warnings)?,
        "infinite" => {
            let k = positive(ps, "illuminance")?.map(|e| e / PI).unwrap_or(1.0);
            t.insert("type".into(), "constant".into());
            t.insert("radiance".into(), rgb_value(emitted(ps, "L", k)?));
        }
        other => return Err(err(format!("light \"{other}\" is not supported (point, spot, distant, infinite; diffuse area lights)"))),
    }
    ps.finish(&what)?;
    Ok(t)
}

fn spot(ps: &ParamList, m: DMat4, t: &mut Table) -> Result<(), SceneError> {
    let cone = ps.float("coneangle", 30.0)?;
    let delta = ps.float("conedeltaangle", 5.0)?;
    if !(cone > 0.0 && cone <= 180.0 && (0.0..=cone).contains(&delta)) {
        return Err(SceneError(
            "needs 0 < coneangle ≤ 180 and 0 ≤ conedeltaangle ≤ coneangle".into(),
        ));
    }
    let (cos_end, cos_start) = (cone.to_radians().cos(), (cone - delta).to_radians().cos());
    let k = positive(ps, "power")?
        .map(|p| p / (2.0 * PI * ((1.0 - cos_start) + (cos_start - cos_end) / 2.0)))
        .unwrap_or(1.0);
    let from = point_param(ps, "from", DVec3::ZERO)?;
    let to = point_param(ps, "to", DVec3::Z)?;
    let d = m
        .transform_vector3(to - from)
        .try_normalize()
        .ok_or_else(|| SceneError("from = to".into()))?;
    t.insert("type".into(), "spot".into());
    t.insert("position".into(), vec3(m.transform_point3(from)));
    t.insert("direction".into(), vec3(d));
    t.insert("intensity".into(), rgb_value(emitted(ps, "I", k)?));
    t.insert("cone_angle".into(), cone.into());
    t.insert("falloff_start".into(), (cone - delta).into());
    t.insert("curve".into(), "smoothstep".into());
    Ok(())
}

/// An `AreaLightSource "diffuse"` on a shape of surface `area` (world
/// units; `None` when unknown) as the shape's `emitter` table.
pub fn area_light(ty: &str, ps: &ParamList, area: Option<f64>) -> Result<Table, SceneError> {
    if ty != "diffuse" {
        return Err(SceneError(format!(
            "area light \"{ty}\" is not supported (diffuse)"
        )));
    }
    if ps.bool("twosided", false)? {
        return Err(SceneError("two-sided area lights are not supported".into()));
    }
    let k = match positive(ps, "power")? {
        None => 1.0,
        Some(p) => {
            let a = area.ok_or_else(|| {
                SceneError("\"power\" needs the shape's area: only on spheres and disks".into())
            })?;
            p / (PI * a)
        }
    };
    let mut t = Table::new();
    t.insert("radiance".into(), rgb_value(emitted(ps, "L", k)?));
    ps.finish(&format!("AreaLightSource \"{ty}\""))?;
    Ok(t)
}

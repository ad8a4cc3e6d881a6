//! `[[shapes]]` as Mitsuba shapes (obj, ply, rectangle, cube, sphere, disk:
//! fogbank's shape types are Mitsuba's), their `to_world` as a matrix, an
//! `area` emitter, `interior`/`exterior` media as references, and their
//! BSDFs: fogbank's BSDF tables use Mitsuba's plugin and parameter names
//! (`world::surfaces::bsdf_desc`), so each key is written as the property
//! of its value's type (a rough model's `distribution` defaults to
//! Beckmann in both).
//! Shape groups become `shapegroup`s (written first: an instance refers to
//! an earlier id) and instances Mitsuba's `instance`.

use super::notes::medium_id;
use super::xml::El;
use fogbank_render::error::SceneError;
use fogbank_render::world::medium::transform;
use fogbank_render::world::surfaces::{ShapeDesc, ShapeType};
use toml::{Table, Value};

/// Every shape: the groups' `shapegroup`s, then the other shapes and the
/// instances in order.
pub fn shapes(descs: &[ShapeDesc]) -> Result<Vec<El>, SceneError> {
    let mut groups: Vec<(&str, El)> = Vec::new();
    let mut rest = Vec::new();
    for (i, s) in descs.iter().enumerate() {
        match (&s.group, s.kind) {
            (Some(g), ShapeType::Instance) => {
                s.check_instance(&format!("shapes.{i}"))?;
                let mut e = El::plugin("shape", "instance");
                e.push(El::new("ref").attr("id", group_id(g)));
                e.push(El::matrix(
                    "to_world",
                    super::media::rows(transform(&s.to_world)),
                ));
                rest.push(e);
            }
            (Some(g), _) => {
                let at = match groups.iter().position(|(name, _)| name == g) {
                    Some(k) => k,
                    None => {
                        let e = El::plugin("shape", "shapegroup").attr("id", group_id(g));
                        groups.push((g.as_str(), e));
                        groups.len() - 1
                    }
                };
                groups[at].1.push(shape(s, i)?);
            }
            (None, _) => rest.push(shape(s, i)?),
        }
    }
    Ok(groups.into_iter().map(|(_, e)| e).chain(rest).collect())
}

/// The XML id of shape group `name`.
fn group_id(name: &str) -> String {
    format!("group_{name}")
}

/// Shape `i` as a `<shape>`.
fn shape(s: &ShapeDesc, i: usize) -> Result<El, SceneError> {
    let key = format!("shapes.{i}");
    if s.kind == ShapeType::Instance {
        s.check_instance(&key)?;
        return Err(SceneError(format!(
            "{key}.group: an instance needs a group"
        )));
    }
    s.to_world.check(&format!("{key}.to_world"))?;
    let ty = Value::try_from(s.kind)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default();
    let mut e = El::plugin("shape", &ty);
    if let Some(f) = &s.file {
        e.push(El::string("filename", f));
    }
    e.push(El::matrix(
        "to_world",
        super::media::rows(transform(&s.to_world)),
    ));
    if s.flip_normals {
        e.push(El::boolean("flip_normals", true));
    }
    if s.face_normals {
        e.push(El::boolean("face_normals", true));
    }
    if ty == "obj" {
        e.push(El::boolean("flip_tex_coords", s.flip_tex_coords));
    }
    if let Some(b) = &s.bsdf {
        let t = Value::try_from(b).map_err(|x| SceneError(format!("{key}.bsdf: {x}")))?;
        e.push(bsdf(t.as_table().cloned().unwrap_or_default(), "", &key)?);
    }
    if let Some(em) = &s.emitter {
        e.push(El::plugin("emitter", "area").child(El::rgb("radiance", em.radiance)));
    }
    for (name, m) in [("interior", s.interior), ("exterior", s.exterior)] {
        if let Some(m) = m {
            e.push(El::new("ref").attr("name", name).attr("id", medium_id(m)));
        }
    }
    Ok(e)
}

/// A BSDF table as `<bsdf>` (named `name` when not empty).
fn bsdf(mut t: Table, name: &str, key: &str) -> Result<El, SceneError> {
    let ty = match t.remove("type") {
        Some(Value::String(s)) => s,
        _ => return Err(SceneError(format!("{key}.bsdf: no type"))),
    };
    let mut e = El::plugin("bsdf", &ty);
    if !name.is_empty() {
        e = e.attr("name", name);
    }
    for (k, v) in t {
        let k_path = format!("{key}.bsdf.{k}");
        match (k.as_str(), v) {
            ("bsdf" | "front" | "back", Value::Table(inner)) => {
                e.push(bsdf(inner, "", &k_path)?);
            }
            (_, Value::Table(tex)) => e.push(texture(tex, &k, &k_path)?),
            (_, v) => e.push(property(&k, &v, &k_path)?),
        }
    }
    Ok(e)
}

/// A texture table (`checkerboard` or `bitmap`) as `<texture name>`.
fn texture(mut t: Table, name: &str, key: &str) -> Result<El, SceneError> {
    let ty = t
        .remove("type")
        .and_then(|v| v.as_str().map(str::to_string))
        .ok_or_else(|| SceneError(format!("{key}: a texture needs a type")))?;
    let mut e = El::plugin("texture", &ty).attr("name", name);
    for (k, v) in t {
        match (k.as_str(), v) {
            ("to_uv", Value::Table(uv)) => e.push(to_uv(&uv)),
            (_, v) => e.push(property(&k, &v, &format!("{key}.{k}"))?),
        }
    }
    Ok(e)
}

/// `to_uv = { scale, translate }` as Mitsuba's scale-then-translate.
fn to_uv(uv: &Table) -> El {
    let pair = |k: &str| -> Option<[f64; 2]> {
        let a = uv.get(k)?.as_array()?;
        Some([a.first()?.as_float()?, a.get(1)?.as_float()?])
    };
    let mut t = El::new("transform").attr("name", "to_uv");
    if let Some([x, y]) = pair("scale") {
        t.push(
            El::new("scale")
                .attr("x", super::xml::num(x))
                .attr("y", super::xml::num(y)),
        );
    }
    if let Some([x, y]) = pair("translate") {
        t.push(
            El::new("translate")
                .attr("x", super::xml::num(x))
                .attr("y", super::xml::num(y)),
        );
    }
    t
}

/// A plain value as the property of its type.
fn property(name: &str, v: &Value, key: &str) -> Result<El, SceneError> {
    Ok(match v {
        Value::String(s) => El::string(name, s),
        Value::Boolean(b) => El::boolean(name, *b),
        Value::Float(x) => El::float(name, *x),
        Value::Integer(x) => El::float(name, *x as f64),
        Value::Array(a) if a.len() == 3 => {
            let c: Vec<f32> = a
                .iter()
                .filter_map(|x| x.as_float().or(x.as_integer().map(|i| i as f64)))
                .map(|x| x as f32)
                .collect();
            if c.len() != 3 {
                return Err(SceneError(format!("{key}: expected three numbers")));
            }
            El::rgb(name, [c[0], c[1], c[2]])
        }
        _ => return Err(SceneError(format!("{key}: no Mitsuba property holds {v}"))),
    })
}

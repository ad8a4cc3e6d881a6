//! `<shape>` elements as `[[shapes]]` tables; their media come back as
//! elements for the scene to number.

use super::bsdfs::bsdf;
use super::emitters::area;
use super::plugin::{Ids, Plugin};
use super::xml::{Document, Element};
use fogbank_render::error::SceneError;
use glam::{DMat4, DVec3};
use toml::{Table, Value};

/// A `TransformDesc` table holding `m` as its `matrix` (rows).
pub fn matrix_table(m: DMat4) -> Table {
    let rows = m.transpose().to_cols_array_2d();
    let mut t = Table::new();
    t.insert(
        "matrix".into(),
        Value::Array(
            rows.iter()
                .map(|r| Value::Array(r.iter().map(|&x| Value::Float(x)).collect()))
                .collect(),
        ),
    );
    t
}

/// A shape and the media elements on its inside and outside.
pub struct ShapeOut<'a> {
    pub table: Table,
    pub interior: Option<&'a Element>,
    pub exterior: Option<&'a Element>,
}

pub fn shape<'a>(
    e: &'a Element,
    ids: &'a Ids<'a>,
    doc: &Document,
) -> Result<ShapeOut<'a>, SceneError> {
    let p = Plugin::new(e, ids)?;
    let mut t = Table::new();
    t.insert("type".into(), p.ty.into());
    let mut m = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    match p.ty {
        "obj" | "ply" => {
            let path = p.filename(doc)?;
            t.insert("file".into(), path.display().to_string().into());
            for k in ["face_normals", "flip_normals"] {
                if let Some(b) = p.boolean(k)? {
                    t.insert(k.into(), b.into());
                }
            }
            // Mitsuba flips an OBJ's v coordinate unless told not to.
            if p.ty == "obj" {
                let flip = p.boolean("flip_tex_coords")?.unwrap_or(true);
                t.insert("flip_tex_coords".into(), flip.into());
            }
        }
        "sphere" => {
            let c = DVec3::from(p.vector("center")?.unwrap_or([0.0; 3]));
            let r = p.float("radius")?.unwrap_or(1.0);
            m = m * DMat4::from_translation(c) * DMat4::from_scale(DVec3::splat(r));
        }
        "rectangle" | "cube" | "disk" => {}
        other => {
            return Err(p.error(format!(
                "shape `{other}` is not supported (obj, ply, rectangle, cube, sphere, disk)"
            )))
        }
    }
    if let Some(b) = p.boolean("flip_normals")? {
        t.insert("flip_normals".into(), b.into());
    }
    t.insert("to_world".into(), Value::Table(matrix_table(m)));
    if let Some(b) = p.object("bsdf", "")? {
        t.insert("bsdf".into(), Value::Table(bsdf(b, ids, doc)?));
    }
    if let Some(em) = p.object("emitter", "")? {
        t.insert("emitter".into(), Value::Table(area(em, ids)?));
    }
    let interior = p.object("medium", "interior")?;
    let exterior = p.object("medium", "exterior")?;
    p.finish()?;
    Ok(ShapeOut {
        table: t,
        interior,
        exterior,
    })
}

//! The interpreted scene as a fogbank scene document: the options become
//! `[camera]`, `[render]` and `[integrator]`, lights `[[lights]]`, shapes
//! `[[shapes]]` with their materials and area lights, and the named media
//! that shapes or the camera use `[[media]]`, numbered in order of first
//! use. A shape's `MediumInterface` inside medium is its `interior`; its
//! outside medium, like the camera's, fills the scene's box.

use super::interpret::{Parsed, ShapeEntity};
use super::lights::{area_light, light};
use super::materials::material;
use super::media::medium;
use super::options::{camera_and_render, integrator};
use super::shapes::shape;
use super::state::MaterialRef;
use super::tables::matrix_table;
use super::warnings::Warnings;
use fogbank_math::{Aabb, Vec3};
use fogbank_render::error::SceneError;
use fogbank_render::world::surfaces::ShapeDesc;
use std::collections::BTreeMap;
use std::path::Path;
use toml::{Table, Value};

/// Media in order of first use: per medium, its name, the box of the
/// shapes it is the inside of, and whether it is open (an outside or the
/// camera's).
#[derive(Default)]
struct MediaUse {
    names: Vec<String>,
    interior: Vec<Aabb>,
    open: Vec<bool>,
}

impl MediaUse {
    fn index(&mut self, name: &str) -> usize {
        if let Some(i) = self.names.iter().position(|n| n == name) {
            return i;
        }
        self.names.push(name.into());
        self.interior.push(Aabb::EMPTY);
        self.open.push(false);
        self.names.len() - 1
    }
}

/// The materials: anonymous ones by `MaterialRef::Index` (0: pbrt's
/// default diffuse) and named ones by name.
struct Materials {
    anonymous: Vec<Table>,
    named: BTreeMap<String, Table>,
}

impl Materials {
    fn new(p: &Parsed, warnings: &mut Warnings) -> Result<Materials, SceneError> {
        let mut anonymous = vec![default_material()];
        for m in &p.materials {
            anonymous.push(material(m, warnings)?);
        }
        let mut named = BTreeMap::new();
        for (n, m) in &p.named_materials {
            named.insert(n.clone(), material(m, warnings)?);
        }
        Ok(Materials { anonymous, named })
    }

    fn get(&self, r: &MaterialRef) -> Result<&Table, SceneError> {
        match r {
            MaterialRef::Index(i) => Ok(&self.anonymous[*i]),
            MaterialRef::Named(n, loc) => self
                .named
                .get(n)
                .ok_or_else(|| loc.error(format!("NamedMaterial \"{n}\": no such material"))),
        }
    }
}

fn default_material() -> Table {
    let mut d = Table::new();
    d.insert("type".into(), "diffuse".into());
    d.insert("reflectance".into(), 0.5.into());
    let mut t = Table::new();
    t.insert("type".into(), "twosided".into());
    t.insert("bsdf".into(), Value::Table(d));
    t
}

/// Converts the interpreted scene.
pub fn scene_table(mut p: Parsed) -> Result<Table, SceneError> {
    let mut warnings = std::mem::take(&mut p.warnings);
    let (camera, mut render) = camera_and_render(&p, &mut warnings)?;
    let materials = Materials::new(&p, &mut warnings)?;
    let mut media = MediaUse::default();
    let mut scene_box = Aabb::EMPTY;
    let mut shapes = Vec::new();
    for s in &p.shapes {
        let (t, b, inside) =
            shape_table(s, shapes.len(), &p, &materials, &mut media, &mut warnings)?;
        scene_box = scene_box.union(b);
        if let Some(i) = inside {
            media.interior[i] = media.interior[i].union(b);
        }
        shapes.push(Value::Table(t));
    }
    let groups = object_groups(&p, &materials, &mut media, &mut warnings, &mut shapes)?;
    for (name, to_world, loc) in &p.instances {
        let m = glam::DAffine3::from_mat4(*to_world);
        if !m.is_finite() || m.matrix3.determinant() == 0.0 {
            return Err(loc.error(format!(
                "ObjectInstance \"{name}\": the transform is not invertible"
            )));
        }
        let (group_box, insides) = &groups[name];
        scene_box = scene_box.union(group_box.transformed(&m));
        for (i, b) in insides {
            media.interior[*i] = media.interior[*i].union(b.transformed(&m));
        }
        let mut t = Table::new();
        t.insert("type".into(), "instance".into());
        t.insert("group".into(), name.as_str().into());
        t.insert("to_world".into(), Value::Table(matrix_table(*to_world)));
        shapes.push(Value::Table(t));
    }
    let mut lights = Vec::new();
    for l in &p.lights {
        lights.push(Value::Table(light(l, &p.top_dir, &mut warnings)?));
    }
    if let Some(c) = &p.camera {
        if !c.medium.is_empty() {
            check_medium(&p, &c.medium, &c.entity.loc)?;
            let i = media.index(&c.medium);
            media.open[i] = true;
        }
    }
    if let Some(Value::Array(f)) = camera.get("from") {
        let v: Vec<f32> = f
            .iter()
            .filter_map(Value::as_float)
            .map(|x| x as f32)
            .collect();
        let pt = Vec3::new(v[0], v[1], v[2]);
        scene_box = scene_box.union(Aabb::new(pt, pt));
    }
    let pad = 0.01 * (scene_box.max - scene_box.min).max_element().max(1e-3);
    let open_box = Aabb::new(scene_box.min - pad, scene_box.max + pad);
    let mut media_tables = Vec::new();
    for (i, name) in media.names.iter().enumerate() {
        let b = if media.open[i] {
            open_box
        } else {
            media.interior[i]
        };
        media_tables.push(Value::Table(medium(
            name,
            &p.media[name],
            b,
            &p.top_dir,
            &mut warnings,
        )?));
    }
    for (name, m) in &p.media {
        if !media.names.contains(name) {
            warnings.warn(format!("{}: medium \"{name}\" is never used", m.entity.loc));
        }
    }
    let integ = integrator(p.integrator.as_ref(), !media_tables.is_empty(), &mut render)?;
    let mut out = Table::new();
    out.insert("camera".into(), Value::Table(camera));
    out.insert("render".into(), Value::Table(render));
    out.insert("integrator".into(), Value::Table(integ));
    out.insert("media".into(), Value::Array(media_tables));
    out.insert("lights".into(), Value::Array(lights));
    out.insert("shapes".into(), Value::Array(shapes));
    Ok(out)
}

fn check_medium(p: &Parsed, name: &str, loc: &super::tokenizer::Loc) -> Result<(), SceneError> {
    if p.media.contains_key(name) {
        Ok(())
    } else {
        Err(loc.error(format!(
            "MediumInterface: no medium \"{name}\" (MakeNamedMedium it first)"
        )))
    }
}

/// Per instanced object, the box of its shapes and of each medium they
/// are the inside of (in the object's space).
type GroupBoxes = BTreeMap<String, (Aabb, Vec<(usize, Aabb)>)>;

/// The shapes of every object some `ObjectInstance` places, appended to
/// `shapes` as members of a shape group of the object's name.
fn object_groups(
    p: &Parsed,
    materials: &Materials,
    media: &mut MediaUse,
    warnings: &mut Warnings,
    shapes: &mut Vec<Value>,
) -> Result<GroupBoxes, SceneError> {
    let mut groups = GroupBoxes::new();
    for (name, _, _) in &p.instances {
        if groups.contains_key(name) {
            continue;
        }
        let (mut group_box, mut insides) = (Aabb::EMPTY, Vec::new());
        for s in &p.objects[name] {
            let (mut t, b, inside) = shape_table(s, shapes.len(), p, materials, media, warnings)?;
            group_box = group_box.union(b);
            insides.extend(inside.map(|i| (i, b)));
            t.insert("group".into(), name.as_str().into());
            shapes.push(Value::Table(t));
        }
        groups.insert(name.clone(), (group_box, insides));
    }
    Ok(groups)
}

/// The `index`-th shape's table, its bounds and the medium it is the
/// inside of (whose box the caller grows); the open media recorded.
fn shape_table(
    s: &ShapeEntity,
    index: usize,
    p: &Parsed,
    materials: &Materials,
    media: &mut MediaUse,
    warnings: &mut Warnings,
) -> Result<(Table, Aabb, Option<usize>), SceneError> {
    let out = shape(s, &p.top_dir, warnings)?;
    let mut t = out.table;
    t.insert(
        "bsdf".into(),
        Value::Table(materials.get(&s.attrs.material)?.clone()),
    );
    if let Some(al) = &s.attrs.area_light {
        let (ty, ps, loc) = &**al;
        let e = area_light(ty, ps, out.area).map_err(|e| {
            if e.0.starts_with(&loc.to_string()) {
                e
            } else {
                loc.error(e.0)
            }
        })?;
        t.insert("emitter".into(), Value::Table(e));
    }
    let bounds = shape_bounds(&t, index).map_err(|e| s.entity.loc.error(e.0))?;
    let (inside, outside) = (&s.attrs.inside, &s.attrs.outside);
    let mut interior = None;
    if !inside.is_empty() && inside != outside {
        check_medium(p, inside, &s.entity.loc)?;
        let i = media.index(inside);
        interior = Some(i);
        t.insert("interior".into(), (i as i64).into());
    }
    if !outside.is_empty() {
        check_medium(p, outside, &s.entity.loc)?;
        let i = media.index(outside);
        media.open[i] = true;
        t.insert("exterior".into(), (i as i64).into());
    }
    Ok((t, bounds, interior))
}

fn shape_bounds(t: &Table, i: usize) -> Result<Aabb, SceneError> {
    let d: ShapeDesc = Value::Table(t.clone())
        .try_into()
        .map_err(|e| SceneError(format!("{e}")))?;
    d.bounds(i, Path::new("."))
}

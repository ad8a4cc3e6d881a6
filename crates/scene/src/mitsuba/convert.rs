//! A Mitsuba scene document as a fogbank scene description: the sensor
//! becomes `[camera]` and `[render]`, the integrator `[integrator]`,
//! emitters `[[lights]]`, shapes `[[shapes]]`, and the media they (or the
//! sensor) name `[[media]]`, numbered in order of first mention.

use super::emitters::light;
use super::media::medium;
use super::plugin::{Ids, Plugin};
use super::shapes::shape;
use super::xml::{Document, Element};
use fogbank_math::{Aabb, Vec3};
use fogbank_render::error::SceneError;
use fogbank_render::world::surfaces::ShapeDesc;
use glam::{DMat4, DVec3};
use std::path::Path;
use toml::{Table, Value};

/// Every element with an `id`, at any depth.
fn collect_ids<'a>(e: &'a Element, ids: &mut Ids<'a>) -> Result<(), SceneError> {
    for c in &e.children {
        if let Some(id) = c.attr("id") {
            if c.tag != "ref" && ids.insert(id, c).is_some() {
                return Err(c.error(format!("id `{id}` is used twice")));
            }
        }
        collect_ids(c, ids)?;
    }
    Ok(())
}

/// Media in order of first mention, with how they are used.
#[derive(Default)]
struct MediaUse<'a> {
    media: Vec<&'a Element>,
    /// Per medium: the union of the boxes of shapes it is the interior of.
    interior_box: Vec<Aabb>,
    /// Per medium: named as an exterior or by the sensor (unbounded).
    open: Vec<bool>,
}

impl<'a> MediaUse<'a> {
    fn index(&mut self, m: &'a Element) -> usize {
        if let Some(i) = self.media.iter().position(|x| std::ptr::eq(*x, m)) {
            return i;
        }
        self.media.push(m);
        self.interior_box.push(Aabb::EMPTY);
        self.open.push(false);
        self.media.len() - 1
    }
}

/// Converts the document; relative file names in it are made absolute.
pub fn scene_table(doc: &Document) -> Result<Table, SceneError> {
    let mut ids = Ids::new();
    collect_ids(&doc.root, &mut ids)?;
    let root = &doc.root;
    let mut out = Table::new();
    let (mut lights, mut shapes) = (Vec::new(), Vec::new());
    let mut media = MediaUse::default();
    let mut scene_box = Aabb::EMPTY;
    let mut groups = ShapeGroups::default();
    let mut sensor_medium = None;
    let no_media = ignores_media(root.children.iter().find(|c| c.tag == "integrator"));
    if root.children.iter().all(|c| c.tag != "integrator") {
        // Mitsuba's default integrator is `path`.
        let mut t = Table::new();
        t.insert("type".into(), "volpath".into());
        t.insert("max_depth".into(), 100_000.into());
        t.insert("rr_depth".into(), 5.into());
        out.insert("integrator".into(), Value::Table(t));
    }
    for c in &root.children {
        match c.tag.as_str() {
            "integrator" => {
                let mut t = integrator(c, &ids)?;
                if out.contains_key("integrator") {
                    return Err(c.error("a second <integrator>"));
                }
                t.insert("type".into(), "volpath".into());
                out.insert("integrator".into(), Value::Table(t));
            }
            "sensor" => {
                if out.contains_key("camera") {
                    return Err(c.error("a second <sensor>"));
                }
                let (camera, render, m) = sensor(c, &ids)?;
                sensor_medium = m.filter(|_| !no_media);
                out.insert("camera".into(), Value::Table(camera));
                out.insert("render".into(), Value::Table(render));
            }
            "emitter" => lights.push(Value::Table(light(c, &ids, doc)?)),
            // Converted where an instance places it.
            "shape" if c.attr("type") == Some("shapegroup") => {}
            "shape" if c.attr("type") == Some("instance") => {
                let (t, b) = groups.instance(c, (&ids, doc), no_media, &mut media, &mut shapes)?;
                scene_box = scene_box.union(b);
                shapes.push(Value::Table(t));
            }
            "shape" => {
                let i = shapes.len();
                let (table, b, inside) = shape_table(c, (&ids, doc), i, no_media, &mut media)?;
                scene_box = scene_box.union(b);
                if let Some(m) = inside {
                    media.interior_box[m] = media.interior_box[m].union(b);
                }
                shapes.push(Value::Table(table));
            }
            // Named objects are converted where they are referenced.
            "bsdf" | "texture" | "medium" | "volume" | "phase" if c.attr("id").is_some() => {}
            _ => return Err(c.error("is not supported at the top level of a scene")),
        }
    }
    if no_media {
        path_depth_counts_agree(&out, &shapes).map_err(|m| root.error(m))?;
    }
    if let Some(m) = sensor_medium {
        let i = media.index(m);
        media.open[i] = true;
    }
    if let Some(p) = camera_position(&out) {
        scene_box = scene_box.union(Aabb::new(p, p));
    }
    // An unbounded medium fills the scene's box, a little enlarged.
    let pad = 0.01 * (scene_box.max - scene_box.min).max_element().max(1e-3);
    let open_box = Aabb::new(scene_box.min - pad, scene_box.max + pad);
    let mut media_tables = Vec::new();
    for (i, m) in media.media.iter().enumerate() {
        let b = if media.open[i] {
            open_box
        } else {
            media.interior_box[i]
        };
        media_tables.push(Value::Table(medium(m, &ids, doc, b)?));
    }
    out.insert("media".into(), Value::Array(media_tables));
    out.insert("lights".into(), Value::Array(lights));
    out.insert("shapes".into(), Value::Array(shapes));
    Ok(out)
}

/// A `<shape>` (the `index`-th) as a `[[shapes]]` table with its bounds
/// and the medium it is the inside of (whose box the caller grows: a
/// group's shapes lie where its instances place them); its exterior
/// medium is recorded as open (unless the integrator ignores media).
fn shape_table<'a>(
    c: &'a Element,
    (ids, doc): (&'a Ids<'a>, &'a Document),
    index: usize,
    no_media: bool,
    media: &mut MediaUse<'a>,
) -> Result<(Table, Aabb, Option<usize>), SceneError> {
    let s = shape(c, ids, doc)?;
    let mut table = s.table;
    let bounds = shape_bounds(&table, index).map_err(|e| c.error(e.0))?;
    let interior = s.interior.filter(|_| !no_media).map(|m| media.index(m));
    if let Some(i) = interior {
        table.insert("interior".into(), (i as i64).into());
    }
    if let Some(m) = s.exterior.filter(|_| !no_media) {
        let i = media.index(m);
        media.open[i] = true;
        table.insert("exterior".into(), (i as i64).into());
    }
    Ok((table, bounds, interior))
}

/// The `shapegroup`s that instances place, converted at their first
/// instance: per group (by id) the box of its shapes and of each medium
/// they are the inside of, in the group's space.
#[derive(Default)]
struct ShapeGroups {
    boxes: std::collections::BTreeMap<String, (Aabb, Vec<(usize, Aabb)>)>,
}

impl ShapeGroups {
    /// An `instance` as a `[[shapes]]` table and its world box; its group's
    /// shapes are appended to `shapes` the first time.
    fn instance<'a>(
        &mut self,
        c: &'a Element,
        (ids, doc): (&'a Ids<'a>, &'a Document),
        no_media: bool,
        media: &mut MediaUse<'a>,
        shapes: &mut Vec<Value>,
    ) -> Result<(Table, Aabb), SceneError> {
        let p = Plugin::new(c, ids)?;
        let group = p
            .object("shape", "")?
            .filter(|g| g.attr("type") == Some("shapegroup"))
            .ok_or_else(|| c.error("an instance needs a <ref id> to a shapegroup"))?;
        let m = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
        p.finish()?;
        let id = group
            .attr("id")
            .ok_or_else(|| group.error("a shapegroup needs an `id` to be instanced"))?;
        if !self.boxes.contains_key(id) {
            let placed = self.members(group, (ids, doc), no_media, media, shapes)?;
            self.boxes.insert(id.to_string(), placed);
        }
        let affine = glam::DAffine3::from_mat4(m);
        if !affine.is_finite() || affine.matrix3.determinant() == 0.0 {
            return Err(c.error("to_world: not invertible"));
        }
        let (group_box, insides) = &self.boxes[id];
        for (i, b) in insides {
            media.interior_box[*i] = media.interior_box[*i].union(b.transformed(&affine));
        }
        let mut t = Table::new();
        t.insert("type".into(), "instance".into());
        t.insert("group".into(), id.into());
        t.insert(
            "to_world".into(),
            Value::Table(super::shapes::matrix_table(m)),
        );
        Ok((t, group_box.transformed(&affine)))
    }

    /// A shapegroup's shapes, appended to `shapes` as members of group `id`.
    fn members<'a>(
        &mut self,
        group: &'a Element,
        (ids, doc): (&'a Ids<'a>, &'a Document),
        no_media: bool,
        media: &mut MediaUse<'a>,
        shapes: &mut Vec<Value>,
    ) -> Result<(Aabb, Vec<(usize, Aabb)>), SceneError> {
        let id = group.attr("id").unwrap_or_default();
        let g = Plugin::new(group, ids)?;
        let (mut group_box, mut insides) = (Aabb::EMPTY, Vec::new());
        for s in g.objects("shape")? {
            if matches!(s.attr("type"), Some("shapegroup" | "instance")) {
                return Err(s.error("shapegroups and instances do not nest (as in Mitsuba 3)"));
            }
            let (mut t, b, inside) = shape_table(s, (ids, doc), shapes.len(), no_media, media)?;
            if t.contains_key("emitter") {
                return Err(s.error("a shapegroup's shapes cannot emit (as in Mitsuba 3)"));
            }
            group_box = group_box.union(b);
            insides.extend(inside.map(|i| (i, b)));
            t.insert("group".into(), id.into());
            shapes.push(Value::Table(t));
        }
        g.finish()?;
        Ok((group_box, insides))
    }
}

/// The converted camera's position (`camera.from`), which the box of
/// unbounded media must hold.
fn camera_position(out: &Table) -> Option<Vec3> {
    let Some(Value::Table(cam)) = out.get("camera") else {
        return None;
    };
    let Some(Value::Array(o)) = cam.get("from") else {
        return None;
    };
    let p: Vec<f32> = o
        .iter()
        .filter_map(|v| v.as_float())
        .map(|x| x as f32)
        .collect();
    Some(Vec3::new(p[0], p[1], p[2]))
}

fn shape_bounds(t: &Table, i: usize) -> Result<Aabb, SceneError> {
    let d: ShapeDesc = Value::Table(t.clone())
        .try_into()
        .map_err(|e| SceneError(format!("{e}")))?;
    d.bounds(i, Path::new("."))
}

/// Mitsuba's `path` and `direct` count a passage through a `null` or
/// `thindielectric` surface as a bounce, fogbank's volpath (and Mitsuba's)
/// do not: with a finite depth such scenes would render differently.
fn path_depth_counts_agree(out: &Table, shapes: &[Value]) -> Result<(), String> {
    let depth = out
        .get("integrator")
        .and_then(|i| i.get("max_depth"))
        .and_then(|d| d.as_integer())
        .unwrap_or(100_000);
    fn passes(b: &Value) -> bool {
        match b.get("type").and_then(|t| t.as_str()) {
            Some("null") | Some("thindielectric") => true,
            _ => ["bsdf", "front", "back"]
                .iter()
                .any(|k| b.get(*k).is_some_and(passes)),
        }
    }
    let passing = shapes.iter().any(|s| s.get("bsdf").is_some_and(passes));
    if depth < 100_000 && passing {
        return Err(
            "Mitsuba's `path` and `direct` integrators count a passage through a null or \
                    thin dielectric surface as a bounce, which fogbank does not: with a finite \
                    max_depth use volpath (or max_depth -1)"
                .into(),
        );
    }
    Ok(())
}

/// Whether Mitsuba's integrator `e` (absent: its default, `path`) renders
/// without participating media: `path` and `direct` ignore them.
fn ignores_media(e: Option<&Element>) -> bool {
    match e {
        None => true,
        Some(e) => match e.attr("type") {
            Some("moment") => ignores_media(e.children.iter().find(|c| c.tag == "integrator")),
            Some("path") | Some("direct") => true,
            _ => false,
        },
    }
}

/// `volpath`, `volpathmis` (the same for fogbank's achromatic media), a
/// `moment` around one (fogbank always writes the variance), or `path` or
/// `direct`, which are fogbank's volpath without media (Mitsuba's ignore
/// them) and, for `direct`, stopping at the first surface (Mitsuba's
/// max_depth 2; its emitter and BSDF sample counts change only the noise).
fn integrator(e: &Element, ids: &Ids) -> Result<Table, SceneError> {
    let p = Plugin::new(e, ids)?;
    if p.ty == "moment" {
        let inner = p.objects("integrator")?;
        p.finish()?;
        return match inner.as_slice() {
            [one] => integrator(one, ids),
            _ => Err(e.error("a moment integrator wraps one integrator")),
        };
    }
    if p.ty == "direct" {
        for k in ["emitter_samples", "bsdf_samples", "shading_samples"] {
            p.integer(k)?;
        }
        if p.boolean("hide_emitters")? == Some(true) {
            return Err(p.error("hide_emitters = true is not supported"));
        }
        p.finish()?;
        let mut t = Table::new();
        t.insert("max_depth".into(), 1.into());
        return Ok(t);
    }
    if !["volpath", "volpathmis", "path"].contains(&p.ty) {
        return Err(p.error(format!(
            "integrator `{}` is not supported (volpath, volpathmis, path, direct, moment)",
            p.ty
        )));
    }
    let mut t = Table::new();
    // Mitsuba counts path segments (1: emitters seen directly); fogbank
    // counts scattering vertices.
    match p.integer("max_depth")?.unwrap_or(-1) {
        -1 => {
            t.insert("max_depth".into(), 100_000.into());
        }
        d if (2..=100_001).contains(&d) => {
            t.insert("max_depth".into(), (d - 1).into());
        }
        d => {
            return Err(p.error(format!(
                "max_depth {d}: fogbank supports -1 (unlimited) or 2..=100001"
            )))
        }
    }
    let rr = p.integer("rr_depth")?.unwrap_or(5);
    if !(1..=100_000).contains(&rr) {
        return Err(p.error(format!("rr_depth {rr} is outside 1..=100000")));
    }
    t.insert("rr_depth".into(), rr.into());
    if p.boolean("hide_emitters")? == Some(true) {
        return Err(p.error("hide_emitters = true is not supported"));
    }
    p.finish()?;
    Ok(t)
}

/// `perspective` with its `film` (hdrfilm, box filter) and `sampler`
/// (independent): the camera, the render settings and the sensor's medium.
fn sensor<'a>(
    e: &'a Element,
    ids: &'a Ids<'a>,
) -> Result<(Table, Table, Option<&'a Element>), SceneError> {
    let p = Plugin::new(e, ids)?;
    if p.ty != "perspective" {
        return Err(p.error(format!("sensor `{}` is not supported (perspective)", p.ty)));
    }
    let fov = p.float("fov")?;
    let focal_length = p.string("focal_length")?;
    let axis = p.string("fov_axis")?;
    // Mitsuba's defaults: rays start 0.01 along the view axis and end at 10⁴.
    let near = p.float("near_clip")?.unwrap_or(0.01);
    let far = p.float("far_clip")?.unwrap_or(1e4);
    if !(near > 0.0 && far > near) {
        return Err(p.error(format!(
            "near_clip {near} / far_clip {far}: need 0 < near < far"
        )));
    }
    let m = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    let film = p
        .object("film", "")?
        .ok_or_else(|| p.error("needs a <film>"))?;
    let (w, h) = film_size(film, ids)?;
    let mut render = Table::new();
    if let Some(s) = p.object("sampler", "")? {
        let sp = Plugin::new(s, ids)?;
        if sp.ty != "independent" {
            return Err(sp.error("only the independent sampler is supported"));
        }
        render.insert(
            "spp".into(),
            sp.integer("sample_count")?.unwrap_or(4).into(),
        );
        if let Some(seed) = sp.integer("seed")? {
            render.insert("seed".into(), seed.into());
        }
        sp.finish()?;
    }
    let medium = match p.object("medium", "medium")? {
        Some(m) => Some(m),
        None => p.object("medium", "")?,
    };
    p.finish()?;
    let fov =
        horizontal_fov(fov, focal_length, axis, w as f64 / h as f64).map_err(|m| e.error(m))?;
    let origin = m.transform_point3(DVec3::ZERO);
    let forward = m.transform_vector3(DVec3::Z).normalize_or_zero();
    let up = m.transform_vector3(DVec3::Y).normalize_or_zero();
    let left = m.transform_vector3(DVec3::X);
    // Mitsuba's camera x points left; a mirrored transform (a negative
    // scale, as `fogbank convert` writes pbrt's left-handed cameras) flips
    // the image, which is fogbank's `mirror`.
    let handed = up.cross(forward).dot(left);
    if !(handed.is_finite() && handed != 0.0) {
        return Err(p_error(e, "the sensor's to_world is degenerate"));
    }
    let mirror = handed < 0.0;
    let v = |d: DVec3| Value::Array(d.to_array().iter().map(|&x| Value::Float(x)).collect());
    let mut camera = Table::new();
    camera.insert("from".into(), v(origin));
    camera.insert("to".into(), v(origin + forward));
    camera.insert("up".into(), v(up));
    camera.insert("fov".into(), fov.into());
    camera.insert("fov_axis".into(), "x".into());
    camera.insert("width".into(), w.into());
    camera.insert("height".into(), h.into());
    camera.insert("near_clip".into(), near.into());
    camera.insert("far_clip".into(), far.into());
    if mirror {
        camera.insert("mirror".into(), true.into());
    }
    Ok((camera, render, medium))
}

/// The horizontal field of view in degrees, as Mitsuba's `parse_fov`
/// (sensor.cpp) computes it for an image of `aspect` = width / height:
/// `fov` along `fov_axis` (x, y, diagonal, smaller, larger; default x), or
/// without `fov` the 35 mm equivalent `focal_length` (default "50mm"),
/// whose field of view is along the diagonal of a 36 × 24 mm frame:
/// 2 atan(√(36² + 24²) / 2f).
pub fn horizontal_fov(
    fov: Option<f64>,
    focal_length: Option<&str>,
    axis: Option<&str>,
    aspect: f64,
) -> Result<f64, String> {
    let (fov, axis) = match (fov, focal_length) {
        (Some(_), Some(_)) => {
            return Err("give either `fov` or `focal_length`, not both (as Mitsuba)".into())
        }
        (Some(fov), None) => {
            let axis = axis.unwrap_or("x").to_ascii_lowercase();
            let axis = match axis.as_str() {
                "smaller" if aspect > 1.0 => "y".to_string(),
                "smaller" => "x".to_string(),
                "larger" if aspect > 1.0 => "x".to_string(),
                "larger" => "y".to_string(),
                _ => axis,
            };
            (fov, axis)
        }
        // Mitsuba ignores `fov_axis` here: a focal length is diagonal.
        (None, f) => {
            let f = f.unwrap_or("50mm");
            let mm = f
                .trim()
                .strip_suffix("mm")
                .unwrap_or(f.trim())
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or_else(|| format!("focal_length `{f}` is not a length like \"35mm\""))?;
            let diagonal = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
            (
                2.0 * (diagonal / (2.0 * mm)).atan().to_degrees(),
                "diagonal".to_string(),
            )
        }
    };
    let half = (0.5 * fov.to_radians()).tan();
    let x = match axis.as_str() {
        "x" => fov,
        "y" => 2.0 * (half * aspect).atan().to_degrees(),
        "diagonal" => {
            let width = 2.0 * half / (1.0 + 1.0 / (aspect * aspect)).sqrt();
            2.0 * (0.5 * width).atan().to_degrees()
        }
        other => {
            return Err(format!(
                "fov_axis `{other}` (x, y, diagonal, smaller, larger)"
            ))
        }
    };
    if !(x > 0.0 && x < 180.0) {
        return Err(format!(
            "the horizontal field of view {x}° is outside (0, 180)"
        ));
    }
    Ok(x)
}

fn p_error(e: &Element, what: &str) -> SceneError {
    e.error(what)
}

fn film_size(film: &Element, ids: &Ids) -> Result<(i64, i64), SceneError> {
    let f = Plugin::new(film, ids)?;
    if f.ty != "hdrfilm" {
        return Err(f.error("only hdrfilm is supported"));
    }
    let w = f.integer("width")?.unwrap_or(768);
    let h = f.integer("height")?.unwrap_or(576);
    if !(1..=1 << 16).contains(&w) || !(1..=1 << 16).contains(&h) {
        return Err(f.error(format!("{w}×{h} pixels is outside 1..=65536 per side")));
    }
    match f.string("pixel_format")? {
        None | Some("rgb") | Some("rgba") => {}
        Some(o) => return Err(f.error(format!("pixel_format `{o}` (rgb)"))),
    }
    match f.string("component_format")? {
        None | Some("float32") => {}
        Some(o) => return Err(f.error(format!("component_format `{o}` (float32)"))),
    }
    match f.object("rfilter", "")? {
        Some(r) if r.attr("type") == Some("box") && r.children.is_empty() => {}
        Some(r) => return Err(r.error("only the box filter is supported")),
        None => {
            return Err(f.error(
                "Mitsuba's default filter is gaussian; fogbank has the box filter only: add <rfilter type=\"box\"/>",
            ))
        }
    }
    f.finish()?;
    Ok((w, h))
}

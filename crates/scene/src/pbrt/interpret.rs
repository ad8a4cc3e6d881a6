//! The statement interpreter: reads pbrt-v4 statements off the token
//! stream, keeps the graphics state, and collects the scene's entities
//! (camera, film, sampler, integrator, media, lights, materials, shapes)
//! with the transforms and attributes current where they appear. The
//! mapping onto fogbank's description comes after, from these.
//!
//! Object instancing stays instancing: an object's shapes become a shape
//! group (built once) and each `ObjectInstance` an `instance` placing it
//! with the transform current there, as pbrt-v4 shares them.

use super::cursor::Cursor;
use super::params::{Param, ParamList};
use super::state::{self, Attributes, MaterialRef};
use super::tokenizer::{Loc, TokenKind};
use super::warnings::Warnings;
use fogbank_render::error::SceneError;
use glam::DMat4;
use std::collections::BTreeMap;
use std::rc::Rc;

/// A statement's type string, parameters and place.
#[derive(Debug)]
pub struct Entity {
    pub ty: String,
    pub params: ParamList,
    pub loc: Loc,
}

impl Entity {
    /// `Shape "sphere"`, for messages.
    pub fn what(&self, statement: &str) -> String {
        format!("{statement} \"{}\"", self.ty)
    }
}

pub struct Placed {
    pub entity: Entity,
    /// The current transform where it appeared (camera: world-from-camera).
    pub ctm: DMat4,
    /// The medium: the camera's and a light's outside medium.
    pub medium: String,
}

#[derive(Clone)]
pub struct ShapeEntity {
    pub entity: Rc<Entity>,
    pub ctm: DMat4,
    pub attrs: Attributes,
}

#[derive(Default)]
pub struct Parsed {
    pub camera: Option<Placed>,
    pub film: Option<Entity>,
    pub sampler: Option<Entity>,
    pub integrator: Option<Entity>,
    pub filter: Option<Entity>,
    pub options: ParamList,
    pub media: BTreeMap<String, Placed>,
    pub lights: Vec<Placed>,
    /// `Material` statements in order; a shape's `MaterialRef::Index` is
    /// one more than the index here (0 is the default, diffuse).
    pub materials: Vec<Entity>,
    pub named_materials: BTreeMap<String, Entity>,
    pub shapes: Vec<ShapeEntity>,
    /// `ObjectBegin` … `ObjectEnd`: each object's shapes, each under its own
    /// transform in the object's space.
    pub objects: BTreeMap<String, Vec<ShapeEntity>>,
    /// `ObjectInstance`s in order: the object, the current transform, and
    /// where.
    pub instances: Vec<(String, DMat4, Loc)>,
    pub warnings: Warnings,
    /// The top-level file's folder, against which file names resolve.
    pub top_dir: std::path::PathBuf,
}

struct Interpreter {
    cur: Cursor,
    out: Parsed,
    attrs: Attributes,
    stack: Vec<(Attributes, Loc)>,
    coord_systems: BTreeMap<String, DMat4>,
    in_world: bool,
    /// Inside `ObjectBegin`: its name, place and shapes so far.
    object: Option<(String, Loc, Vec<ShapeEntity>)>,
}

/// Reads every statement of the scene text `text` (the file `file`).
pub fn interpret(text: &str, file: &std::path::Path) -> Result<Parsed, SceneError> {
    let mut it = Interpreter {
        cur: Cursor::new(text, file)?,
        out: Parsed::default(),
        attrs: Attributes::default(),
        stack: Vec::new(),
        coord_systems: BTreeMap::new(),
        in_world: false,
        object: None,
    };
    while let Some(t) = it.cur.next_token() {
        let TokenKind::Word(name) = &t.kind else {
            return Err(t
                .loc
                .error(format!("expected a statement, found {}", t.describe())));
        };
        it.statement(name, &t.loc)?;
    }
    if let Some((_, loc)) = it.stack.last() {
        return Err(loc.error("AttributeBegin without AttributeEnd"));
    }
    if let Some((name, loc, _)) = &it.object {
        return Err(loc.error(format!("ObjectBegin \"{name}\" without ObjectEnd")));
    }
    it.out.top_dir = it.cur.top_dir().to_path_buf();
    Ok(it.out)
}

impl Interpreter {
    fn statement(&mut self, name: &str, loc: &Loc) -> Result<(), SceneError> {
        if self.transform_statement(name, loc)? || self.attribute_statement(name, loc)? {
            return Ok(());
        }
        if self.options_statement(name, loc)? {
            return Ok(());
        }
        self.world_statement(name, loc)
    }

    /// The parameter list that follows a statement's arguments.
    fn params(&mut self) -> Result<ParamList, SceneError> {
        let mut list = ParamList::default();
        while self
            .cur
            .peek()
            .is_some_and(|t| matches!(t.kind, TokenKind::Str(_)))
        {
            let decl = self.cur.next_token().expect("peeked");
            let first = self.cur.expect(&decl.loc, "a parameter value")?;
            let mut values = Vec::new();
            if first.kind == TokenKind::Open {
                loop {
                    let t = self.cur.expect(&decl.loc, "]")?;
                    match t.kind {
                        TokenKind::Close => break,
                        TokenKind::Open => {
                            return Err(t.loc.error("`[` inside a parameter's values"))
                        }
                        _ => values.push(t),
                    }
                }
            } else if first.kind == TokenKind::Close {
                return Err(first.loc.error("`]` without `[`"));
            } else {
                values.push(first);
            }
            list.push(Param::new(&decl, values)?)?;
        }
        Ok(list)
    }

    /// `list` with the `Attribute` defaults of `target` it does not give.
    fn with_defaults(&self, target: &str, mut list: ParamList) -> ParamList {
        for (t, p) in &self.attrs.defaults {
            if t == target && !list.has(&p.name) {
                list.params.push(p.clone());
            }
        }
        list
    }

    /// A statement's type string and parameters, with the `Attribute`
    /// defaults of `target` (`shape`, `light`, `material`; "" for none).
    fn entity(&mut self, loc: &Loc, what: &str, target: &str) -> Result<Entity, SceneError> {
        let (ty, tloc) = self.cur.string(loc, what)?;
        let params = self.params()?;
        let params = self.with_defaults(target, params);
        Ok(Entity {
            ty,
            params,
            loc: tloc,
        })
    }

    fn apply(&mut self, m: DMat4) {
        self.attrs.ctm *= m;
    }

    fn transform_statement(&mut self, name: &str, loc: &Loc) -> Result<bool, SceneError> {
        let mut nums = |n: usize| self.cur.numbers(loc, n, name);
        let m = match name {
            "Identity" => {
                self.attrs.ctm = DMat4::IDENTITY;
                return Ok(true);
            }
            "Translate" => state::translate(three(&nums(3)?)),
            "Scale" => state::scale(three(&nums(3)?)),
            "Rotate" => {
                let v = nums(4)?;
                state::rotate(v[0], [v[1], v[2], v[3]])
                    .ok_or_else(|| loc.error("Rotate about a zero axis"))?
            }
            "LookAt" => {
                let v: [f64; 9] = nums(9)?.try_into().expect("9 numbers");
                state::look_at(&v).ok_or_else(|| {
                    loc.error("LookAt: eye equals look, or up is parallel to the view direction")
                })?
            }
            "Transform" | "ConcatTransform" => {
                let v: [f64; 16] = nums(16)?.try_into().expect("16 numbers");
                let m = state::matrix(&v);
                if name == "Transform" {
                    self.attrs.ctm = m;
                    return Ok(true);
                }
                m
            }
            "CoordinateSystem" => {
                let (n, _) = self.cur.string(loc, "a coordinate system name")?;
                self.coord_systems.insert(n, self.attrs.ctm);
                return Ok(true);
            }
            "CoordSysTransform" => {
                let (n, nloc) = self.cur.string(loc, "a coordinate system name")?;
                self.attrs.ctm = *self.coord_systems.get(&n).ok_or_else(|| {
                    nloc.error(format!("CoordSysTransform: no coordinate system \"{n}\""))
                })?;
                return Ok(true);
            }
            "ActiveTransform" | "TransformTimes" => {
                return Err(loc.error(format!(
                    "{name}: motion blur (animated transforms) is not supported"
                )))
            }
            _ => return Ok(false),
        };
        self.apply(m);
        Ok(true)
    }

    fn attribute_statement(&mut self, name: &str, loc: &Loc) -> Result<bool, SceneError> {
        match name {
            "AttributeBegin" | "TransformBegin" => {
                if self.stack.len() >= 1024 {
                    return Err(loc.error("AttributeBegin nested deeper than 1024"));
                }
                self.stack.push((self.attrs.clone(), loc.clone()));
            }
            "AttributeEnd" | "TransformEnd" => {
                let (saved, _) = self
                    .stack
                    .pop()
                    .ok_or_else(|| loc.error(format!("{name} without AttributeBegin")))?;
                if name == "TransformEnd" {
                    // Only the transform was saved by TransformBegin.
                    self.attrs.ctm = saved.ctm;
                } else {
                    self.attrs = saved;
                }
            }
            "ReverseOrientation" => self.attrs.reverse_orientation ^= true,
            "MediumInterface" => {
                let (inside, _) = self.cur.string(loc, "a medium name")?;
                let outside = if self
                    .cur
                    .peek()
                    .is_some_and(|t| matches!(t.kind, TokenKind::Str(_)))
                {
                    self.cur.string(loc, "a medium name")?.0
                } else {
                    inside.clone()
                };
                self.attrs.inside = inside;
                self.attrs.outside = outside;
            }
            "Attribute" => {
                let e = self.entity(loc, "an attribute target", "")?;
                if !["shape", "light", "material", "medium"].contains(&e.ty.as_str()) {
                    return Err(e.loc.error(format!(
                        "Attribute \"{}\": not a target (shape, light, material, medium)",
                        e.ty
                    )));
                }
                for p in e.params.params {
                    // As in pbrt, a default nobody uses is no error.
                    p.mark_used();
                    self.attrs
                        .defaults
                        .retain(|(t, q)| !(t == &e.ty && q.name == p.name));
                    self.attrs.defaults.push((e.ty.clone(), p));
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    fn options_statement(&mut self, name: &str, loc: &Loc) -> Result<bool, SceneError> {
        let slot = match name {
            "Film" => &mut self.out.film,
            "Sampler" => &mut self.out.sampler,
            "Integrator" => &mut self.out.integrator,
            "PixelFilter" => &mut self.out.filter,
            "Camera" => return self.camera(loc).map(|_| true),
            "WorldBegin" => {
                self.in_world = true;
                self.attrs.ctm = DMat4::IDENTITY;
                self.coord_systems.insert("world".into(), DMat4::IDENTITY);
                return Ok(true);
            }
            "Option" => {
                for p in self.params()?.params {
                    self.out.options.push(p)?;
                }
                return Ok(true);
            }
            "ColorSpace" => {
                let (cs, cloc) = self.cur.string(loc, "a colour space")?;
                if cs != "srgb" {
                    return Err(cloc.error(format!(
                        "ColorSpace \"{cs}\": only \"srgb\" (fogbank renders in linear sRGB)"
                    )));
                }
                return Ok(true);
            }
            "Accelerator" => {
                let e = self.entity(loc, "an accelerator type", "")?;
                self.out.warnings.warn(format!(
                    "{}: Accelerator \"{}\" is ignored (fogbank builds its own BVH)",
                    e.loc, e.ty
                ));
                return Ok(true);
            }
            _ => return Ok(false),
        };
        if slot.is_some() {
            return Err(loc.error(format!("a second {name} statement")));
        }
        let e = {
            let (ty, tloc) = self.cur.string(loc, "a type name")?;
            let params = self.params()?;
            Entity {
                ty,
                params,
                loc: tloc,
            }
        };
        match name {
            "Film" => self.out.film = Some(e),
            "Sampler" => self.out.sampler = Some(e),
            "Integrator" => self.out.integrator = Some(e),
            _ => self.out.filter = Some(e),
        }
        Ok(true)
    }

    fn camera(&mut self, loc: &Loc) -> Result<(), SceneError> {
        if self.in_world || self.out.camera.is_some() {
            return Err(loc.error("Camera: one, before WorldBegin"));
        }
        let e = self.entity(loc, "a camera type", "")?;
        let world_from_camera = self.attrs.ctm.inverse();
        if !world_from_camera.is_finite() {
            return Err(loc.error("Camera: the current transform is singular"));
        }
        self.coord_systems
            .insert("camera".into(), world_from_camera);
        self.out.camera = Some(Placed {
            entity: e,
            ctm: world_from_camera,
            medium: self.attrs.outside.clone(),
        });
        Ok(())
    }

    fn world_statement(&mut self, name: &str, loc: &Loc) -> Result<(), SceneError> {
        match name {
            "Include" | "Import" => {
                let (file, floc) = self.cur.string(loc, "a file name")?;
                if name == "Import" && !self.in_world {
                    return Err(loc.error("Import is only allowed after WorldBegin"));
                }
                self.cur.include(&file, &floc)
            }
            "MakeNamedMedium" => {
                let (n, nloc) = self.cur.string(loc, "a medium name")?;
                let params = self.params()?;
                let params = self.with_defaults("medium", params);
                let ty = params
                    .string("type")?
                    .ok_or_else(|| {
                        nloc.error(format!("MakeNamedMedium \"{n}\": no \"string type\""))
                    })?
                    .to_string();
                if self.out.media.contains_key(&n) {
                    return Err(nloc.error(format!("MakeNamedMedium \"{n}\": redefined")));
                }
                let entity = Entity {
                    ty,
                    params,
                    loc: nloc,
                };
                let placed = Placed {
                    entity,
                    ctm: self.attrs.ctm,
                    medium: String::new(),
                };
                self.out.media.insert(n, placed);
                Ok(())
            }
            _ if !self.in_world => {
                Err(loc.error(format!("unknown statement `{name}` before WorldBegin")))
            }
            _ => self.scene_statement(name, loc),
        }
    }

    fn scene_statement(&mut self, name: &str, loc: &Loc) -> Result<(), SceneError> {
        match name {
            "Material" => {
                let e = self.entity(loc, "a material type", "material")?;
                self.out.materials.push(e);
                self.attrs.material = MaterialRef::Index(self.out.materials.len());
            }
            "MakeNamedMaterial" => {
                let (n, nloc) = self.cur.string(loc, "a material name")?;
                let params = self.params()?;
                let params = self.with_defaults("material", params);
                let ty = params
                    .string("type")?
                    .ok_or_else(|| {
                        nloc.error(format!("MakeNamedMaterial \"{n}\": no \"string type\""))
                    })?
                    .to_string();
                if self.out.named_materials.contains_key(&n) {
                    return Err(nloc.error(format!("MakeNamedMaterial \"{n}\": redefined")));
                }
                self.out.named_materials.insert(
                    n,
                    Entity {
                        ty,
                        params,
                        loc: nloc,
                    },
                );
            }
            "NamedMaterial" => {
                let (n, nloc) = self.cur.string(loc, "a material name")?;
                self.attrs.material = MaterialRef::Named(n, nloc);
            }
            "LightSource" => {
                let entity = self.entity(loc, "a light type", "light")?;
                if self.object.is_some() {
                    return Err(loc.error("LightSource inside ObjectBegin/End"));
                }
                let (ctm, medium) = (self.attrs.ctm, self.attrs.outside.clone());
                self.out.lights.push(Placed {
                    entity,
                    ctm,
                    medium,
                });
            }
            "AreaLightSource" => {
                let e = self.entity(loc, "an area light type", "light")?;
                self.attrs.area_light = Some(Rc::new((e.ty, e.params, e.loc)));
            }
            "Shape" => self.shape(loc)?,
            "ObjectBegin" | "ObjectEnd" | "ObjectInstance" => self.object_statement(name, loc)?,
            "Texture" => {
                return Err(loc.error("Texture: textures are not supported; give constant values"))
            }
            "WorldEnd" => self
                .out
                .warnings
                .warn("WorldEnd is pbrt-v3's; pbrt-v4 ends the scene at the end of the file"),
            _ => return Err(loc.error(format!("unknown statement `{name}`"))),
        }
        Ok(())
    }

    fn shape(&mut self, loc: &Loc) -> Result<(), SceneError> {
        let e = self.entity(loc, "a shape type", "shape")?;
        let s = ShapeEntity {
            entity: Rc::new(e),
            ctm: self.attrs.ctm,
            attrs: self.attrs.clone(),
        };
        match &mut self.object {
            Some((_, oloc, shapes)) => {
                if s.attrs.area_light.is_some() {
                    return Err(oloc.error("an area light inside ObjectBegin/End (pbrt does not allow them in instances)"));
                }
                shapes.push(s);
            }
            None => self.out.shapes.push(s),
        }
        Ok(())
    }

    fn object_statement(&mut self, name: &str, loc: &Loc) -> Result<(), SceneError> {
        match name {
            "ObjectBegin" => {
                let (n, nloc) = self.cur.string(loc, "an object name")?;
                if self.object.is_some() {
                    return Err(nloc.error("ObjectBegin inside ObjectBegin"));
                }
                self.stack.push((self.attrs.clone(), loc.clone()));
                self.object = Some((n, nloc, Vec::new()));
            }
            "ObjectEnd" => {
                let (n, _, shapes) = self
                    .object
                    .take()
                    .ok_or_else(|| loc.error("ObjectEnd without ObjectBegin"))?;
                // As pbrt: an instance places the object's shapes (each
                // under its own transform) by the transform at instancing.
                let (saved, _) = self
                    .stack
                    .pop()
                    .ok_or_else(|| loc.error("ObjectEnd without ObjectBegin"))?;
                self.out.objects.insert(n, shapes);
                self.attrs = saved;
            }
            _ => {
                let (n, nloc) = self.cur.string(loc, "an object name")?;
                if self.object.is_some() {
                    return Err(nloc.error(
                        "ObjectInstance inside ObjectBegin (pbrt-v4 does not nest instances)",
                    ));
                }
                if !self.out.objects.contains_key(&n) {
                    return Err(nloc.error(format!("ObjectInstance: no object \"{n}\"")));
                }
                if self.out.instances.len() >= 1 << 24 {
                    return Err(nloc.error("more than 2²⁴ object instances"));
                }
                self.out.instances.push((n, self.attrs.ctm, nloc));
            }
        }
        Ok(())
    }
}

fn three(v: &[f64]) -> [f64; 3] {
    [v[0], v[1], v[2]]
}

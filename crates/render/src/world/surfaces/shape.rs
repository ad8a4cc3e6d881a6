//! A `[[shapes]]` entry: geometry, placement, material and emission.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `type` | — | `obj`, `ply` (with `file`), `rectangle`, `cube`, `sphere`, `disk` (Mitsuba's unit shapes), `instance` (a placement of a shape group) |
//! | `group` | none | of an `instance`: the shape group it places (required); of any other shape: the group it belongs to — then it is drawn only where instances place the group |
//! | `file` | — | mesh file of `obj` and `ply`, relative to the scene |
//! | `to_world` | identity | `translate`, `rotate` (`[x, y, z, degrees]`), `scale`, as for media |
//! | `flip_normals` | false | turns the shape inside out (Mitsuba's `flip_normals`) |
//! | `face_normals` | false | flat shading: no vertex normals (Mitsuba's `face_normals`); without it a mesh file without normals gets angle-weighted vertex normals, as in Mitsuba (meshes only) |
//! | `flip_tex_coords` | false | v → 1 − v (Mitsuba flips OBJ files' by default; its XML reader sets this; meshes only) |
//! | `bsdf` | diffuse 0.5 (black with an `emitter`, as in Mitsuba) | see [`super::material`] |
//! | `emitter` | none | `{ radiance = [r, g, b] }`: an area light on the front side (Mitsuba's `area`) |
//! | `interior`, `exterior` | none | index of the `[[media]]` entry inside (behind the normals) and outside the shape |
//!
//! A medium named as some shape's `interior` or `exterior` exists only
//! where a ray enters it through such a shape (or starts in it: the camera
//! is placed by casting a ray from it); other media fill their boxes
//! whatever the shapes. A shape whose `interior` and `exterior` differ is a
//! medium transition: a ray that crosses it, or refracts through it,
//! continues in the medium on the side it leaves toward, as in Mitsuba.
//!
//! Shape groups and instances are pbrt-v4's `ObjectBegin`/`ObjectInstance`
//! and Mitsuba 3's `shapegroup`/`instance`: a group's shapes (in the
//! group's space: their own `to_world` places them there) are built once,
//! and each `instance` places them with its `to_world` without copying
//! triangles (a top-level BVH over the instances,
//! [`fogbank_geometry::Instances`]). An `instance` takes only `group` and
//! `to_world`; a group's shapes cannot emit (as in pbrt-v4 and Mitsuba 3),
//! and instances do not nest (an instance belongs to no group). A group
//! with a `sphere` takes only instances that scale uniformly.
//!
//! `sphere` and `disk` are analytic (exact intersection, Mitsuba's normals
//! and UVs; emitting ones are sampled as in Mitsuba: the sphere by the cone
//! it subtends). A sphere's `to_world` must scale uniformly — Mitsuba's
//! sphere has one radius — and a disk's may stretch it into an ellipse.

use super::material::BsdfDesc;
use crate::error::SceneError;
use crate::world::medium::{transform, TransformDesc};
use fogbank_geometry::{load_mesh, shapes, AnalyticShape, Quadric, TriangleMesh};
use fogbank_math::{Aabb, Vec3};
use glam::DAffine3;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ShapeType {
    Obj,
    Ply,
    Rectangle,
    Cube,
    Sphere,
    Disk,
    Instance,
}

/// Mitsuba's `area` emitter.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EmitterDesc {
    pub radiance: [f32; 3],
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ShapeDesc {
    #[serde(rename = "type")]
    pub kind: ShapeType,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    #[serde(default)]
    pub to_world: TransformDesc,
    #[serde(default)]
    pub flip_normals: bool,
    #[serde(default)]
    pub face_normals: bool,
    #[serde(default)]
    pub flip_tex_coords: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bsdf: Option<BsdfDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emitter: Option<EmitterDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interior: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exterior: Option<usize>,
}

impl ShapeDesc {
    /// The BSDF, or Mitsuba's default: grey diffuse, black on an emitter.
    pub fn bsdf(&self) -> BsdfDesc {
        match (&self.bsdf, &self.emitter) {
            (Some(b), _) => b.clone(),
            (None, None) => BsdfDesc::default(),
            (None, Some(_)) => BsdfDesc::Diffuse {
                reflectance: super::material::SpectrumDesc::Grey(0.0),
            },
        }
    }

    /// Its `to_world`, checked: finite and invertible.
    pub fn placement(&self, key: &str) -> Result<DAffine3, SceneError> {
        self.to_world.check(&format!("{key}.to_world"))?;
        let m = transform(&self.to_world);
        if !m.is_finite() || m.matrix3.determinant() == 0.0 {
            return Err(SceneError(format!("{key}.to_world: not invertible")));
        }
        Ok(m)
    }

    /// The shape in world space (a group's shape: in its group's space);
    /// `i` is its `[[shapes]]` index. An `instance` has no geometry of its
    /// own (see [`ShapeDesc::check_instance`]).
    pub fn geometry(&self, i: usize, base: &Path) -> Result<Geometry, SceneError> {
        let key = format!("shapes.{i}");
        self.check_emitter(&key)?;
        if self.group.is_some() && self.emitter.is_some() {
            return Err(SceneError(format!(
                "{key}.emitter: a shape of a group (instanced) cannot emit, as in pbrt-v4 and \
                 Mitsuba 3; place emitting shapes on their own"
            )));
        }
        let m = self.placement(&key)?;
        let quadric = match self.kind {
            ShapeType::Sphere => Quadric::Sphere,
            ShapeType::Disk => Quadric::Disk,
            ShapeType::Instance => {
                return Err(SceneError(format!(
                    "{key}: an instance has no geometry of its own (it places group {:?})",
                    self.group.as_deref().unwrap_or("")
                )))
            }
            _ => return Ok(Geometry::Mesh(self.mesh(&key, base, m)?)),
        };
        for (set, name) in [
            (self.face_normals, "face_normals"),
            (self.flip_tex_coords, "flip_tex_coords"),
        ] {
            if set {
                return Err(SceneError(format!(
                    "{key}.{name}: only obj and ply meshes take it, not a {}",
                    quadric.name()
                )));
            }
        }
        if self.file.is_some() {
            return Err(SceneError(format!(
                "{key}.file: only obj and ply shapes read files"
            )));
        }
        if quadric == Quadric::Sphere && !scales_uniformly(&m.matrix3) {
            return Err(SceneError(format!(
                "{key}.to_world: a sphere takes a uniform scale (Mitsuba's sphere has one \
                 radius); an ellipsoid needs a mesh (obj or ply)"
            )));
        }
        AnalyticShape::new(quadric, m, self.flip_normals)
            .map(Geometry::Analytic)
            .ok_or_else(|| {
                SceneError(format!(
                    "{key}.to_world: not invertible, or places the shape beyond f32 range"
                ))
            })
    }

    /// The box of the shape's finite vertices (or of its analytic shape).
    pub fn bounds(&self, i: usize, base: &Path) -> Result<Aabb, SceneError> {
        Ok(match self.geometry(i, base)? {
            Geometry::Analytic(a) => a.bounds(),
            Geometry::Mesh(mesh) => {
                let mut b = Aabb::new(Vec3::INFINITY, Vec3::NEG_INFINITY);
                for p in mesh.positions.iter().filter(|p| p.is_finite()) {
                    b = Aabb::new(b.min.min(*p), b.max.max(*p));
                }
                b
            }
        })
    }

    /// An `instance`'s keys: `group` (required) and `to_world`, nothing
    /// else; returns the group's name and the placement.
    pub fn check_instance(&self, key: &str) -> Result<(&str, DAffine3), SceneError> {
        let group = self
            .group
            .as_deref()
            .ok_or_else(|| SceneError(format!("{key}: an instance needs `group`")))?;
        let set = [
            (self.file.is_some(), "file"),
            (self.flip_normals, "flip_normals"),
            (self.face_normals, "face_normals"),
            (self.flip_tex_coords, "flip_tex_coords"),
            (self.bsdf.is_some(), "bsdf"),
            (self.emitter.is_some(), "emitter"),
            (self.interior.is_some(), "interior"),
            (self.exterior.is_some(), "exterior"),
        ];
        if let Some((_, name)) = set.iter().find(|(s, _)| *s) {
            return Err(SceneError(format!(
                "{key}.{name}: an instance takes only `group` and `to_world` (its group's \
                 shapes carry materials, emission and media)"
            )));
        }
        Ok((group, self.placement(key)?))
    }

    fn check_emitter(&self, key: &str) -> Result<(), SceneError> {
        match &self.emitter {
            Some(e) if !e.radiance.iter().all(|v| v.is_finite() && *v >= 0.0) => {
                Err(SceneError(format!(
                    "{key}.emitter.radiance: {:?} has a negative or non-finite channel",
                    e.radiance
                )))
            }
            _ => Ok(()),
        }
    }

    /// A mesh shape's triangles in world space (`m`: its `to_world`).
    fn mesh(&self, key: &str, base: &Path, m: DAffine3) -> Result<TriangleMesh, SceneError> {
        let mut mesh = match (self.kind, &self.file) {
            (ShapeType::Obj | ShapeType::Ply, None) => {
                return Err(SceneError(format!("{key}: `file` is required")))
            }
            (ShapeType::Obj | ShapeType::Ply, Some(f)) => {
                load_mesh(&base.join(f)).map_err(|e| SceneError(format!("{key}: {e}")))?
            }
            (_, Some(_)) => {
                return Err(SceneError(format!(
                    "{key}.file: only obj and ply shapes read files"
                )))
            }
            (ShapeType::Rectangle, None) => shapes::rectangle(),
            (ShapeType::Cube, None) => shapes::cube(),
            (ShapeType::Sphere | ShapeType::Disk | ShapeType::Instance, None) => {
                unreachable!("geometry() builds analytic shapes and refuses instances")
            }
        };
        if self.face_normals {
            mesh.normals.clear();
        } else if mesh.normals.is_empty() && matches!(self.kind, ShapeType::Obj | ShapeType::Ply) {
            mesh.normals = mesh.angle_weighted_normals();
        }
        if self.flip_tex_coords {
            mesh.uvs.iter_mut().for_each(|uv| uv.y = 1.0 - uv.y);
        }
        if self.flip_normals {
            mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
            mesh.normals.iter_mut().for_each(|n| *n = -*n);
        }
        mesh.transform(&glam::DMat4::from(m).as_mat4());
        Ok(mesh)
    }
}

/// What a `[[shapes]]` entry builds.
pub enum Geometry {
    Mesh(TriangleMesh),
    Analytic(AnalyticShape),
}

/// Whether `m` is a rotation (or reflection) times one scale: orthogonal
/// columns of equal length, to a relative 10⁻⁴.
pub(crate) fn scales_uniformly(m: &glam::DMat3) -> bool {
    let c = [m.x_axis, m.y_axis, m.z_axis];
    let l2 = c.map(|v| v.length_squared());
    let tol = 1e-4 * l2[0];
    (l2[1] - l2[0]).abs() <= tol
        && (l2[2] - l2[0]).abs() <= tol
        && [(0, 1), (0, 2), (1, 2)]
            .iter()
            .all(|&(a, b)| c[a].dot(c[b]).abs() <= tol)
}

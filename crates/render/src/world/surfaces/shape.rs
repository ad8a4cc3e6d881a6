//! A `[[shapes]]` entry: geometry, placement, material and emission.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `type` | — | `obj`, `ply` (with `file`), `rectangle`, `cube`, `sphere`, `disk` (Mitsuba's unit shapes) |
//! | `file` | — | mesh file of `obj` and `ply`, relative to the scene |
//! | `to_world` | identity | `translate`, `rotate` (`[x, y, z, degrees]`), `scale`, as for media |
//! | `flip_normals` | false | turns the shape inside out (Mitsuba's `flip_normals`) |
//! | `face_normals` | false | flat shading: no vertex normals (Mitsuba's `face_normals`); without it a mesh file without normals gets angle-weighted vertex normals, as in Mitsuba |
//! | `flip_tex_coords` | false | v → 1 − v (Mitsuba flips OBJ files' by default; its XML reader sets this) |
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
//! `sphere` and `disk` are tessellated (128 × 256 and 256 triangles) until
//! analytic shapes exist.

use super::material::BsdfDesc;
use crate::error::SceneError;
use crate::world::medium::{transform, TransformDesc};
use fogbank_geometry::{load_mesh, shapes, TriangleMesh};
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

    /// The shape's triangles in world space; `i` is its `[[shapes]]` index.
    pub fn mesh(&self, i: usize, base: &Path) -> Result<TriangleMesh, SceneError> {
        let key = format!("shapes.{i}");
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
            (ShapeType::Sphere, None) => shapes::sphere(128),
            (ShapeType::Disk, None) => shapes::disk(256),
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
        self.to_world.check(&format!("{key}.to_world"))?;
        let m = transform(&self.to_world);
        if !m.is_finite() || m.matrix3.determinant() == 0.0 {
            return Err(SceneError(format!("{key}.to_world: not invertible")));
        }
        mesh.transform(&glam::DMat4::from(m).as_mat4());
        if let Some(e) = &self.emitter {
            if !e.radiance.iter().all(|v| v.is_finite() && *v >= 0.0) {
                return Err(SceneError(format!(
                    "{key}.emitter.radiance: {:?} has a negative or non-finite channel",
                    e.radiance
                )));
            }
        }
        Ok(mesh)
    }
}

//! Shapes' geometry gathered, shape by shape, into one mesh and its
//! analytic shapes: the world's (shapes of no group) or one shape group's.
//! Emitting shapes' lights are made here too (the world's only: a group's
//! shapes cannot emit).

use super::surface_hit::Shape;
use crate::lights::area::AreaTriangle;
use crate::lights::disk::DiskLight;
use crate::lights::sphere::SphereLight;
use crate::lights::Light;
use crate::SceneError;
use fogbank_geometry::{AnalyticShape, MeshAccel, Quadric, TriangleMesh};
use fogbank_math::Vec3;
use glam::Vec2;

/// One mesh of every triangle (with per-vertex normals and uvs, zero where
/// a shape has none), the analytic shapes, and per primitive its shape
/// (index into the scene's shapes). Emitting analytic shapes' lights come
/// before the emitting triangles' (the light BVH takes a run of triangles
/// at the end), so `first_triangle` and `first_light` count within their
/// kind until [`Gathered::finish`].
#[derive(Default)]
pub(super) struct Gathered {
    mesh: TriangleMesh,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    analytic: Vec<AnalyticShape>,
    /// The shapes gathered here (indices into the scene's shapes).
    members: Vec<u32>,
    shape_of: Vec<u32>,
    analytic_shape_of: Vec<u32>,
    analytic_lights: Vec<Light>,
    triangle_lights: Vec<Light>,
}

impl Gathered {
    /// Adds analytic shape `a` as scene shape `index`; `key` names it in errors.
    pub(super) fn add_analytic(
        &mut self,
        key: &str,
        index: u32,
        a: AnalyticShape,
        shape: &mut Shape,
    ) -> Result<(), SceneError> {
        shape.analytic = true;
        shape.first_triangle = self.analytic.len() as u32;
        shape.first_light = self.analytic_lights.len() as u32;
        if let Some(le) = shape.emission {
            self.analytic_lights.push(
                analytic_light(&a, le)
                    .ok_or_else(|| SceneError(format!("{key}: its area is not finite")))?,
            );
        }
        self.analytic.push(a);
        self.analytic_shape_of.push(index);
        self.members.push(index);
        Ok(())
    }

    /// Adds `mesh` as scene shape `index`.
    pub(super) fn add_mesh(&mut self, index: u32, mesh: TriangleMesh, shape: &mut Shape) {
        let all = &mut self.mesh;
        let v0 = all.positions.len() as u32;
        shape.first_triangle = all.triangles.len() as u32;
        shape.first_light = self.triangle_lights.len() as u32;
        shape.has_normals = !mesh.normals.is_empty();
        shape.has_uvs = !mesh.uvs.is_empty();
        if let Some(le) = shape.emission {
            self.triangle_lights.extend(triangle_lights(&mesh, le));
        }
        let nv = mesh.positions.len();
        self.normals.extend(if shape.has_normals {
            mesh.normals
        } else {
            vec![Vec3::ZERO; nv]
        });
        self.uvs.extend(if shape.has_uvs {
            mesh.uvs
        } else {
            vec![Vec2::ZERO; nv]
        });
        all.positions.extend(mesh.positions);
        all.triangles
            .extend(mesh.triangles.iter().map(|t| t.map(|v| v + v0)));
        self.shape_of
            .extend(std::iter::repeat_n(index, mesh.triangles.len()));
        self.members.push(index);
    }

    /// The acceleration structure and per primitive its shape; the
    /// gathered shapes' first primitive and light are put in the scene's
    /// numbering and their lights appended to `lights`.
    pub(super) fn finish(
        self,
        shapes: &mut [Shape],
        lights: &mut Vec<Light>,
    ) -> (MeshAccel, Vec<u32>) {
        let Gathered {
            mut mesh,
            normals,
            uvs,
            analytic,
            members,
            mut shape_of,
            analytic_shape_of,
            analytic_lights,
            triangle_lights,
        } = self;
        let (triangles, scene_lights) = (mesh.triangles.len() as u32, lights.len() as u32);
        for &i in &members {
            let s = &mut shapes[i as usize];
            if s.analytic {
                s.first_triangle += triangles;
                s.first_light += scene_lights;
            } else {
                s.first_light += scene_lights + analytic_lights.len() as u32;
            }
        }
        lights.extend(analytic_lights);
        lights.extend(triangle_lights);
        shape_of.extend(analytic_shape_of);
        mesh.normals = normals;
        mesh.uvs = uvs;
        (MeshAccel::with_analytic(mesh, analytic), shape_of)
    }
}

/// The light of an emitting analytic shape (`None`: its area overflows).
fn analytic_light(a: &AnalyticShape, radiance: Vec3) -> Option<Light> {
    let m = a.to_world.matrix3;
    let centre = a.to_world.translation.as_vec3();
    match a.quadric {
        Quadric::Sphere => {
            let radius = m.x_axis.length() as f32;
            let l = SphereLight {
                centre,
                radius,
                radiance,
                inward: a.flip,
            };
            (l.area().is_finite() && radius > 0.0).then_some(Light::Sphere(l))
        }
        Quadric::Disk => {
            let n = (a.to_object.matrix3.transpose() * glam::DVec3::Z).normalize();
            let n = n.as_vec3() * if a.flip { -1.0 } else { 1.0 };
            let (u, v) = (m.x_axis.as_vec3(), m.y_axis.as_vec3());
            DiskLight::new(centre, u, v, n, radiance).map(Light::Disk)
        }
    }
}

/// One area light per triangle of an emitting mesh (a degenerate triangle
/// keeps its place with zero area, so light indices follow triangles).
fn triangle_lights(mesh: &TriangleMesh, le: Vec3) -> impl Iterator<Item = Light> + '_ {
    (0..mesh.len()).map(move |t| {
        let n = mesh.triangles[t]
            .iter()
            .map(|&v| mesh.normals.get(v as usize).copied().unwrap_or(Vec3::ZERO))
            .sum();
        let tri = AreaTriangle::new(mesh.corners(t), n, le);
        Light::Area(tri.unwrap_or(AreaTriangle {
            p0: Vec3::ZERO,
            e1: Vec3::ZERO,
            e2: Vec3::ZERO,
            n: Vec3::Z,
            area: 0.0,
            radiance: Vec3::ZERO,
        }))
    })
}

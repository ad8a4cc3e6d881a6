//! Every shape of the scene in one BVH over one triangle mesh and the
//! analytic spheres and disks: closest hits with their shading data,
//! occlusion of shadow rays (index-matched `null` boundaries let light
//! through), and the area light behind each emitting triangle, sphere or
//! disk.

use super::material::Material;
use super::shape::{Geometry, ShapeDesc};
use crate::error::SceneError;
use crate::lights::area::AreaTriangle;
use crate::lights::disk::DiskLight;
use crate::lights::sphere::SphereLight;
use crate::lights::Light;
use crate::world::bitmap::BitmapFiles;
use crate::world::medium::SceneMedium;
use fogbank_geometry::{AnalyticShape, MeshAccel, MeshHit, Quadric, TriangleMesh};
use fogbank_math::{Aabb, Ray, Vec3};
use glam::Vec2;
use std::path::Path;

/// A built shape: its material and emission, and where its primitives
/// (its triangles, or its one analytic shape) and (when it emits) its
/// lights sit in the scene's arrays.
#[derive(Clone, Debug)]
pub struct Shape {
    pub material: Material,
    pub emission: Option<Vec3>,
    /// Its first primitive (the BVH's index: triangles, then analytic
    /// shapes).
    pub first_triangle: u32,
    /// Index in `World::lights` of the light of `first_triangle` (the
    /// shape's triangles' lights follow in order; degenerate triangles get
    /// a zero-radiance light so the indices stay aligned).
    pub first_light: u32,
    /// World media inside (behind the normals) and outside.
    pub interior: Option<usize>,
    pub exterior: Option<usize>,
    has_normals: bool,
    has_uvs: bool,
    /// An analytic sphere or disk (one primitive, after the triangles).
    analytic: bool,
}

impl Shape {
    /// Whether its triangles carry vertex normals (else flat) and UVs.
    pub fn shading_data(&self) -> (bool, bool) {
        (self.has_normals, self.has_uvs)
    }
}

/// What an integrator needs at a surface hit.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub t: f32,
    pub p: Vec3,
    /// Unit geometric normal (from the winding).
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normals, else `ng`).
    pub ns: Vec3,
    pub uv: Vec2,
    pub shape: u32,
    /// The triangle or analytic shape hit (the BVH's primitive index).
    pub primitive: u32,
}

impl SurfaceHit {
    /// A ray leaving the hit along `d`, its origin pushed off the surface
    /// to the side `d` goes (relative to the position's magnitude, so rays
    /// do not hit the triangle they leave).
    pub fn spawn(&self, d: Vec3) -> Ray {
        Ray::new(offset(self.p, self.ng, d), d)
    }
}

/// `p` moved off a surface with normal `ng` toward the side of `d`.
pub fn offset(p: Vec3, ng: Vec3, d: Vec3) -> Vec3 {
    let eps = 1e-5 * (1.0 + p.abs().max_element());
    p + ng * if ng.dot(d) >= 0.0 { eps } else { -eps }
}

#[derive(Clone, Debug)]
pub struct Surfaces {
    accel: MeshAccel,
    shape_of: Vec<u32>,
    pub shapes: Vec<Shape>,
    /// Per world medium: whether shapes bound it (it exists only where
    /// rays enter it through them).
    bounded: Vec<bool>,
    /// The medium the camera starts in.
    pub camera_medium: Option<usize>,
    /// Per shape: whether light passes straight through (null, thin
    /// dielectric), looked up for every triangle a shadow ray tests.
    passes: Vec<bool>,
    /// See [`Surfaces::shadows_walk`].
    walk: bool,
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

/// The world medium of `[[media]]` entry `entry` for `key`; instanced
/// media cannot be bounded by a shape.
fn world_medium(media: &[SceneMedium], entry: usize, key: &str) -> Result<usize, SceneError> {
    let mut of_entry = media.iter().enumerate().filter(|(_, m)| m.entry == entry);
    match (of_entry.next(), of_entry.next()) {
        (Some((w, _)), None) => Ok(w),
        (None, _) => Err(SceneError(format!("{key}: there is no media.{entry}"))),
        (Some(_), Some(_)) => Err(SceneError(format!(
            "{key}: media.{entry} has instances; a shape bounds one medium"
        ))),
    }
}

/// The shapes' geometry as it is gathered, shape by shape: one mesh of
/// every triangle (with per-vertex normals and uvs, zero where a shape has
/// none), the analytic shapes, and per primitive its shape. Emitting
/// analytic shapes' lights come before the emitting triangles' (the light
/// BVH takes a run of triangles at the end), so `first_triangle` and
/// `first_light` count within their kind until [`Gathered::finish`].
#[derive(Default)]
struct Gathered {
    mesh: TriangleMesh,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    analytic: Vec<AnalyticShape>,
    shapes: Vec<Shape>,
    shape_of: Vec<u32>,
    analytic_shape_of: Vec<u32>,
    analytic_lights: Vec<Light>,
    triangle_lights: Vec<Light>,
}

impl Gathered {
    fn add_analytic(
        &mut self,
        i: usize,
        a: AnalyticShape,
        mut shape: Shape,
    ) -> Result<(), SceneError> {
        shape.analytic = true;
        shape.first_triangle = self.analytic.len() as u32;
        shape.first_light = self.analytic_lights.len() as u32;
        if let Some(le) = shape.emission {
            self.analytic_lights.push(
                analytic_light(&a, le)
                    .ok_or_else(|| SceneError(format!("shapes.{i}: its area is not finite")))?,
            );
        }
        self.analytic.push(a);
        self.analytic_shape_of.push(i as u32);
        self.shapes.push(shape);
        Ok(())
    }

    fn add_mesh(&mut self, i: usize, mesh: TriangleMesh, mut shape: Shape) {
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
            .extend(std::iter::repeat_n(i as u32, mesh.triangles.len()));
        self.shapes.push(shape);
    }

    /// The acceleration structure, the shapes with their first primitive
    /// and light in the scene's numbering, and per primitive its shape;
    /// the emitting shapes' lights are appended to `lights`.
    fn finish(self, lights: &mut Vec<Light>) -> (MeshAccel, Vec<Shape>, Vec<u32>) {
        let Gathered {
            mut mesh,
            normals,
            uvs,
            analytic,
            mut shapes,
            mut shape_of,
            analytic_shape_of,
            analytic_lights,
            triangle_lights,
        } = self;
        let (triangles, scene_lights) = (mesh.triangles.len() as u32, lights.len() as u32);
        for s in &mut shapes {
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
        (MeshAccel::with_analytic(mesh, analytic), shapes, shape_of)
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

impl Surfaces {
    /// The shapes, their emitting triangles appended to `lights`; `media`
    /// are the world's media (which shapes may bound) and `camera` the
    /// camera position.
    pub fn build(
        descs: &[ShapeDesc],
        base: &Path,
        media: &[SceneMedium],
        camera: Vec3,
        lights: &mut Vec<Light>,
    ) -> Result<Surfaces, SceneError> {
        let mut bounded = vec![false; media.len()];
        let mut g = Gathered::default();
        let files = BitmapFiles::new(base);
        for (i, d) in descs.iter().enumerate() {
            let geometry = d.geometry(i, base)?;
            let material = d.bsdf().build_with(&format!("shapes.{i}.bsdf"), &files)?;
            let emission = d.emitter.as_ref().map(|e| Vec3::from(e.radiance));
            if emission.is_some() && material.is_null() {
                return Err(SceneError(format!(
                    "shapes.{i}: an emitter needs a BSDF other than null"
                )));
            }
            let mut side = |m: Option<usize>, name: &str| -> Result<Option<usize>, SceneError> {
                m.map(|e| {
                    let w = world_medium(media, e, &format!("shapes.{i}.{name}"))?;
                    bounded[w] = true;
                    Ok(w)
                })
                .transpose()
            };
            let (interior, exterior) =
                (side(d.interior, "interior")?, side(d.exterior, "exterior")?);
            let shape = Shape {
                material,
                emission,
                first_triangle: 0,
                first_light: 0,
                interior,
                exterior,
                has_normals: false,
                has_uvs: false,
                analytic: false,
            };
            match geometry {
                Geometry::Analytic(a) => g.add_analytic(i, a, shape)?,
                Geometry::Mesh(mesh) => g.add_mesh(i, mesh, shape),
            }
        }
        let (accel, shapes, shape_of) = g.finish(lights);
        let passes: Vec<bool> = shapes.iter().map(|s| s.material.passes_light()).collect();
        let partial = shapes
            .iter()
            .any(|s| s.material.passes_light() && !s.material.is_null());
        let walk = bounded.iter().any(|&b| b) || partial;
        let mut s = Surfaces {
            accel,
            shape_of,
            shapes,
            bounded,
            camera_medium: None,
            passes,
            walk,
        };
        s.camera_medium = s.medium_at(camera);
        Ok(s)
    }

    /// Whether some shape is a medium transition (then shadow rays follow
    /// the media across null boundaries).
    pub fn has_transitions(&self) -> bool {
        self.bounded.iter().any(|&b| b)
    }

    /// Whether world medium `i` exists only inside the shapes that bound it.
    pub fn bounds_medium(&self, i: usize) -> bool {
        self.bounded.get(i).copied().unwrap_or(false)
    }

    /// The bounded medium around `p` (`None`: only unbounded media): the
    /// side from which a ray from `p` meets its first medium transition.
    pub fn medium_at(&self, p: Vec3) -> Option<usize> {
        // An irrational-ish direction, unlikely to graze edges of axis-aligned shapes.
        let mut ray = Ray::new(p, Vec3::new(0.5377, 0.6193, 0.5721).normalize());
        for _ in 0..1024 {
            let h = self.intersect(&ray, f32::INFINITY)?;
            let s = &self.shapes[h.shape as usize];
            if s.interior != s.exterior {
                return if ray.d.dot(h.ng) > 0.0 {
                    s.interior
                } else {
                    s.exterior
                };
            }
            ray = h.spawn(ray.d);
        }
        None
    }

    /// The medium a ray continues in after leaving hit `h` along `w`,
    /// having arrived in `current`: the shape's side `w` points to when
    /// the shape is a medium transition, else `current`.
    pub fn target_medium(&self, h: &SurfaceHit, w: Vec3, current: Option<usize>) -> Option<usize> {
        let s = &self.shapes[h.shape as usize];
        if s.interior == s.exterior {
            current
        } else if w.dot(h.ng) > 0.0 {
            s.exterior
        } else {
            s.interior
        }
    }

    /// The triangles and their BVH (what a GPU port uploads).
    pub fn accel(&self) -> &MeshAccel {
        &self.accel
    }

    /// Per primitive (triangles in mesh order, then analytic shapes), the
    /// index of its shape.
    pub fn shape_of(&self) -> &[u32] {
        &self.shape_of
    }

    /// Whether light passes straight through shape `i` (null, thin dielectric).
    pub fn shape_passes_light(&self, i: usize) -> bool {
        self.passes[i]
    }

    /// Triangles and analytic shapes.
    pub fn primitive_count(&self) -> usize {
        self.shape_of.len()
    }

    /// Bounds of every vertex (finite ones) and analytic shape.
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::new(Vec3::INFINITY, Vec3::NEG_INFINITY);
        let analytic = self.accel.analytic.iter().map(|a| a.bounds());
        let finite = self.accel.mesh.positions.iter().filter(|p| p.is_finite());
        for q in finite.map(|p| Aabb::new(*p, *p)).chain(analytic) {
            b.min = b.min.min(q.min);
            b.max = b.max.max(q.max);
        }
        b
    }

    #[inline]
    fn passes_light(&self, primitive: u32) -> bool {
        self.passes[self.shape_of[primitive as usize] as usize]
    }

    /// The closest surface on the ray in `(0, t_max)`, null boundaries included.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        self.accel.intersect(ray, t_max).map(|h| self.hit(ray, h))
    }

    /// The closest surface that no light passes straight through (not a
    /// null boundary or a thin dielectric).
    pub fn intersect_opaque(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        self.accel
            .intersect_where(ray, t_max, |t| !self.passes_light(t))
            .map(|h| self.hit(ray, h))
    }

    /// Whether a surface that no light passes straight through lies on the
    /// ray in `(0, t_max)`: shadow rays stop at every such surface, as in
    /// Mitsuba's `volpath`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.accel
            .occluded_where(ray, t_max, |t| !self.passes_light(t))
    }

    /// Whether shadow rays must walk from surface to surface: some shape
    /// is a medium transition or passes only part of the light.
    pub fn shadows_walk(&self) -> bool {
        self.walk
    }

    fn hit(&self, ray: &Ray, h: MeshHit) -> SurfaceHit {
        let shape = self.shape_of[h.primitive as usize];
        if let Some(a) = self.accel.analytic_of(h.primitive) {
            let ah = a.hit(ray, h.hit.t);
            return SurfaceHit {
                t: h.hit.t,
                p: ah.p,
                ng: ah.n,
                ns: ah.n,
                uv: ah.uv,
                shape,
                primitive: h.primitive,
            };
        }
        let s = &self.shapes[shape as usize];
        let m = &self.accel.mesh;
        let tri = m.triangles[h.primitive as usize];
        let [p0, p1, p2] = m.corners(h.primitive as usize);
        let b = [1.0 - h.hit.b1 - h.hit.b2, h.hit.b1, h.hit.b2];
        // The barycentric point, not o + t d: it lies on the triangle.
        let p = b[0] * p0 + b[1] * p1 + b[2] * p2;
        let ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let interp = |v: [Vec3; 3]| b[0] * v[0] + b[1] * v[1] + b[2] * v[2];
        let ns = if s.has_normals {
            interp(tri.map(|v| m.normals[v as usize])).normalize_or_zero()
        } else {
            ng
        };
        let uv = if s.has_uvs {
            let u = tri.map(|v| m.uvs[v as usize]);
            b[0] * u[0] + b[1] * u[1] + b[2] * u[2]
        } else {
            // Mitsuba's default parameterisation of a mesh without UVs.
            Vec2::new(b[1], b[2])
        };
        SurfaceHit {
            t: h.hit.t,
            p: if p.is_finite() { p } else { ray.at(h.hit.t) },
            ng,
            ns: if ns == Vec3::ZERO { ng } else { ns },
            uv,
            shape,
            primitive: h.primitive,
        }
    }

    /// The radiance a hit emits back along the ray direction `d` (zero on
    /// a shape without emitter and behind the emitting side), and the index
    /// of its light in `World::lights`.
    pub fn emitted(&self, hit: &SurfaceHit, d: Vec3) -> Option<(Vec3, usize)> {
        let s = &self.shapes[hit.shape as usize];
        let le = s.emission?;
        // Mitsuba's area emitter: the side of the shading normal.
        (hit.ns.dot(d) < 0.0).then(|| {
            (
                le,
                (s.first_light + hit.primitive - s.first_triangle) as usize,
            )
        })
    }
}

//! Every shape of the scene: the world's shapes in one BVH over one
//! triangle mesh and the analytic spheres and disks, shape groups placed by
//! instances beside them ([`super::shape_groups`]); closest hits with their
//! shading data, occlusion of shadow rays (index-matched `null` boundaries
//! let light through), and the area light behind each emitting triangle,
//! sphere or disk.

use super::gathered::Gathered;
use super::shape::{Geometry, ShapeDesc, ShapeType};
use super::shape_groups::{GroupsBuilder, ShapeGroups};
use super::surface_hit::surface_hit;
pub use super::surface_hit::{offset, Shape, SurfaceHit};
use crate::error::SceneError;
use crate::lights::Light;
use crate::world::bitmap::BitmapFiles;
use crate::world::medium::SceneMedium;
use fogbank_geometry::{Instances, MeshAccel, MeshHit};
use fogbank_math::{Aabb, Ray, Vec3};
use std::path::Path;

#[derive(Clone, Debug)]
pub struct Surfaces {
    /// The shapes of no group.
    pub(super) accel: MeshAccel,
    pub(super) shape_of: Vec<u32>,
    pub shapes: Vec<Shape>,
    /// Shape groups and their instances (`None` without instances).
    pub(super) groups: Option<ShapeGroups>,
    /// Per world medium: whether shapes bound it (it exists only where
    /// rays enter it through them).
    pub(super) bounded: Vec<bool>,
    /// The medium the camera starts in.
    pub camera_medium: Option<usize>,
    /// Per shape: whether light passes straight through (null, thin
    /// dielectric), looked up for every triangle a shadow ray tests.
    pub(super) passes: Vec<bool>,
    /// See [`Surfaces::shadows_walk`].
    pub(super) walk: bool,
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
        let mut world = Gathered::default();
        let mut groups = GroupsBuilder::default();
        let mut shapes = Vec::new();
        let files = BitmapFiles::new(base);
        for (i, d) in descs.iter().enumerate() {
            let key = format!("shapes.{i}");
            if d.kind == ShapeType::Instance {
                let (group, to_world) = d.check_instance(&key)?;
                groups.place(&key, group, to_world);
                continue;
            }
            let geometry = d.geometry(i, base)?;
            let material = d.bsdf().build_with(&format!("{key}.bsdf"), &files)?;
            let emission = d.emitter.as_ref().map(|e| Vec3::from(e.radiance));
            if emission.is_some() && material.is_null() {
                return Err(SceneError(format!(
                    "{key}: an emitter needs a BSDF other than null"
                )));
            }
            let mut side = |m: Option<usize>, name: &str| -> Result<Option<usize>, SceneError> {
                m.map(|e| {
                    let w = world_medium(media, e, &format!("{key}.{name}"))?;
                    bounded[w] = true;
                    Ok(w)
                })
                .transpose()
            };
            let (interior, exterior) =
                (side(d.interior, "interior")?, side(d.exterior, "exterior")?);
            let mut shape = Shape {
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
            let index = shapes.len() as u32;
            let g = match &d.group {
                Some(name) => groups.member(name, &geometry),
                None => &mut world,
            };
            match geometry {
                Geometry::Analytic(a) => g.add_analytic(&key, index, a, &mut shape)?,
                Geometry::Mesh(mesh) => g.add_mesh(index, mesh, &mut shape),
            }
            shapes.push(shape);
        }
        let (accel, shape_of) = world.finish(&mut shapes, lights);
        let groups = groups.finish(&mut shapes)?;
        let passes: Vec<bool> = shapes.iter().map(|s| s.material.passes_light()).collect();
        let partial = shapes
            .iter()
            .any(|s| s.material.passes_light() && !s.material.is_null());
        let walk = bounded.iter().any(|&b| b) || partial;
        let mut s = Surfaces {
            accel,
            shape_of,
            shapes,
            groups,
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

    /// The world's triangles and analytic shapes (those of no group) and
    /// their BVH; the groups' are [`Surfaces::groups`].
    pub fn accel(&self) -> &MeshAccel {
        &self.accel
    }

    /// The shape groups' hierarchies (each in its group's space) with
    /// their instances, and per group, per primitive its shape; `None`
    /// without instances.
    pub fn groups(&self) -> Option<(&Instances, &[Vec<u32>])> {
        self.groups.as_ref().map(|g| (&g.instances, g.shape_of()))
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

    /// Bounds of every vertex (finite ones), analytic shape and instance.
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::new(Vec3::INFINITY, Vec3::NEG_INFINITY);
        let analytic = self.accel.analytic.iter().map(|a| a.bounds());
        let finite = self.accel.mesh.positions.iter().filter(|p| p.is_finite());
        let instances = self.groups.as_ref().map(|g| g.instances.bounds());
        for q in finite
            .map(|p| Aabb::new(*p, *p))
            .chain(analytic)
            .chain(instances)
        {
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
        let hit = self.accel.intersect(ray, t_max).map(|h| self.hit(ray, h));
        match &self.groups {
            None => hit,
            Some(g) => g
                .intersect(&self.shapes, ray, hit.map_or(t_max, |h| h.t), |_| true)
                .or(hit),
        }
    }

    /// The closest surface that no light passes straight through (not a
    /// null boundary or a thin dielectric).
    pub fn intersect_opaque(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        let hit = self
            .accel
            .intersect_where(ray, t_max, |t| !self.passes_light(t))
            .map(|h| self.hit(ray, h));
        match &self.groups {
            None => hit,
            Some(g) => g
                .intersect(&self.shapes, ray, hit.map_or(t_max, |h| h.t), |s| {
                    !self.passes[s]
                })
                .or(hit),
        }
    }

    /// Whether a surface that no light passes straight through lies on the
    /// ray in `(0, t_max)`: shadow rays stop at every such surface, as in
    /// Mitsuba's `volpath`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.accel
            .occluded_where(ray, t_max, |t| !self.passes_light(t))
            || self
                .groups
                .as_ref()
                .is_some_and(|g| g.occluded(ray, t_max, |s| !self.passes[s]))
    }

    /// Whether shadow rays must walk from surface to surface: some shape
    /// is a medium transition or passes only part of the light.
    pub fn shadows_walk(&self) -> bool {
        self.walk
    }

    fn hit(&self, ray: &Ray, h: MeshHit) -> SurfaceHit {
        surface_hit(&self.accel, &self.shape_of, &self.shapes, ray, h)
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

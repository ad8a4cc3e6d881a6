//! Shape groups placed by instances (`group` and `type = "instance"` in
//! `[[shapes]]`; pbrt-v4's `ObjectInstance`, Mitsuba 3's `instance`): each
//! group's shapes gathered into one BVH in the group's space, and
//! [`fogbank_geometry::Instances`]' top-level BVH over the placements.
//! Hits found in a group's space are carried to the world here: the point
//! by the instance's map, normals by its inverse transpose — the geometric
//! normal turned when the map mirrors, so that it stays the normal of the
//! placed triangle's winding, as for a copy placed by the same map.

use super::gathered::Gathered;
use super::shape::{scales_uniformly, Geometry};
use super::surface_hit::{surface_hit, Shape, SurfaceHit};
use crate::SceneError;
use fogbank_geometry::{Instance, Instances, MeshAccel, Quadric};
use fogbank_math::{DAffine3, Ray};
use std::collections::HashMap;

/// The groups and instances as `[[shapes]]` is read.
#[derive(Default)]
pub(super) struct GroupsBuilder {
    names: HashMap<String, u32>,
    gathered: Vec<Gathered>,
    /// Whether the group holds a sphere (instances must scale uniformly).
    spheres: Vec<bool>,
    /// Per instance: its key, group name and placement.
    placed: Vec<(String, String, DAffine3)>,
}

impl GroupsBuilder {
    /// The gatherer of group `name`, created at its first member.
    pub(super) fn member(&mut self, name: &str, geometry: &Geometry) -> &mut Gathered {
        let next = self.gathered.len() as u32;
        let g = *self.names.entry(name.to_string()).or_insert(next) as usize;
        if g == self.gathered.len() {
            self.gathered.push(Gathered::default());
            self.spheres.push(false);
        }
        if let Geometry::Analytic(a) = geometry {
            self.spheres[g] |= a.quadric == Quadric::Sphere;
        }
        &mut self.gathered[g]
    }

    /// An instance of group `name` (which its members may still follow).
    pub(super) fn place(&mut self, key: &str, name: &str, to_world: DAffine3) {
        self.placed
            .push((key.to_string(), name.to_string(), to_world));
    }

    /// The groups' hierarchies and the instances' (`None` without
    /// instances; groups without instances are dropped then too).
    pub(super) fn finish(self, shapes: &mut [Shape]) -> Result<Option<ShapeGroups>, SceneError> {
        if self.placed.is_empty() {
            return Ok(None);
        }
        let mut instances = Vec::with_capacity(self.placed.len());
        for (key, name, to_world) in &self.placed {
            let g = *self.names.get(name).ok_or_else(|| {
                let mut known: Vec<&str> = self.names.keys().map(|k| k.as_str()).collect();
                known.sort();
                SceneError(format!(
                    "{key}.group: no shape has group {name:?} (groups: {known:?})"
                ))
            })?;
            if self.spheres[g as usize] && !scales_uniformly(&to_world.matrix3) {
                return Err(SceneError(format!(
                    "{key}.to_world: group {name:?} holds a sphere, which takes a uniform \
                     scale (Mitsuba's sphere has one radius)"
                )));
            }
            instances.push(
                Instance::new(g, *to_world)
                    .ok_or_else(|| SceneError(format!("{key}.to_world: not invertible")))?,
            );
        }
        let mut no_lights = Vec::new();
        let (accels, shape_of): (Vec<MeshAccel>, Vec<Vec<u32>>) = self
            .gathered
            .into_iter()
            .map(|g| g.finish(shapes, &mut no_lights))
            .unzip();
        debug_assert!(no_lights.is_empty(), "a group's shapes cannot emit");
        let instances = Instances::new(accels, instances).map_err(SceneError)?;
        Ok(Some(ShapeGroups {
            instances,
            shape_of,
        }))
    }
}

/// The groups (each a hierarchy in its own space) and their instances.
#[derive(Clone, Debug)]
pub(super) struct ShapeGroups {
    pub(super) instances: Instances,
    /// Per group, per primitive: its shape.
    shape_of: Vec<Vec<u32>>,
}

impl ShapeGroups {
    /// Per group, per primitive: its shape.
    pub(super) fn shape_of(&self) -> &[Vec<u32>] {
        &self.shape_of
    }

    /// The closest hit in `(0, t_max)` on a shape that `keep` accepts (by
    /// shape index), carried to the world.
    pub(super) fn intersect(
        &self,
        shapes: &[Shape],
        ray: &Ray,
        t_max: f32,
        keep: impl Fn(usize) -> bool,
    ) -> Option<SurfaceHit> {
        let h = self.instances.intersect_where(ray, t_max, |g, p| {
            keep(self.shape_of[g as usize][p as usize] as usize)
        })?;
        let inst = &self.instances.instances[h.instance as usize];
        let g = inst.group as usize;
        let local = inst.object_ray(ray);
        let hit = surface_hit(
            &self.instances.groups[g],
            &self.shape_of[g],
            shapes,
            &local,
            h.hit,
        );
        Some(to_world(inst, &shapes[hit.shape as usize], hit))
    }

    /// Whether a shape that `keep` accepts lies on the ray in `(0, t_max)`.
    pub(super) fn occluded(&self, ray: &Ray, t_max: f32, keep: impl Fn(usize) -> bool) -> bool {
        self.instances.occluded_where(ray, t_max, |g, p| {
            keep(self.shape_of[g as usize][p as usize] as usize)
        })
    }
}

/// A hit in a group's space, placed by `inst`.
fn to_world(inst: &Instance, shape: &Shape, mut h: SurfaceHit) -> SurfaceHit {
    h.p = inst.point_to_world(h.p);
    let n = inst.normal_to_world(h.ng);
    if shape.analytic {
        // The analytic shape's normal is its surface normal, placed as such.
        (h.ng, h.ns) = (n, n);
        return h;
    }
    h.ng = if inst.reflects() { -n } else { n };
    let (normals, _) = shape.shading_data();
    let ns = inst.normal_to_world(h.ns);
    h.ns = if normals && ns != fogbank_math::Vec3::ZERO {
        ns
    } else {
        h.ng
    };
    h
}

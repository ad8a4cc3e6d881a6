//! Instancing: shape groups (each a [`MeshAccel`] in its own space, built
//! once) placed any number of times by affine maps, without copying their
//! triangles — the two-level hierarchy of pbrt-v4's `ObjectInstance` and
//! Mitsuba 3's `shapegroup`/`instance`. A top-level [`WideBvh`] over the
//! instances' world boxes finds the instances a ray enters; the ray is
//! carried into the group's space (its direction not renormalised, so
//! distances along it are the world ray's) and the group's own hierarchy
//! answers there, with the closest distance so far as its `t_max`.

use crate::accel::{MeshAccel, MeshHit};
use crate::bvh::Walk;
use crate::wide::WideBvh;
use fogbank_math::{Aabb, DAffine3, Ray, Vec3};

/// One placement of a group.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Index of the group it places.
    pub group: u32,
    /// Group space → world.
    pub to_world: DAffine3,
    /// World → group space (`to_world`'s inverse).
    pub to_object: DAffine3,
}

impl Instance {
    /// `None` when `to_world` is not finite and invertible with a finite
    /// inverse.
    pub fn new(group: u32, to_world: DAffine3) -> Option<Instance> {
        let det = to_world.matrix3.determinant();
        if !(to_world.is_finite() && det != 0.0 && det.is_finite()) {
            return None;
        }
        let to_object = to_world.inverse();
        to_object.is_finite().then_some(Instance {
            group,
            to_world,
            to_object,
        })
    }

    /// The ray in the group's space (in f64, then rounded once): the same
    /// `t` reaches the same point.
    pub fn object_ray(&self, ray: &Ray) -> Ray {
        ray.transformed(&self.to_object)
    }

    /// A group-space point in the world.
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.to_world.transform_point3(p.as_dvec3()).as_vec3()
    }

    /// A group-space normal in the world (inverse transpose), unit length;
    /// zero stays zero.
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        let m = self.to_object.matrix3.transpose();
        (m * n.as_dvec3()).as_vec3().normalize_or_zero()
    }

    /// Whether the map reverses orientation (a triangle's winding normal
    /// then turns against the inverse-transposed one).
    pub fn reflects(&self) -> bool {
        self.to_world.matrix3.determinant() < 0.0
    }

    /// The world box of a group-space box, widened by a few relative ulps:
    /// it must hold every point of the group that the f32 world ray
    /// reaches.
    fn world_box(&self, b: &Aabb) -> Aabb {
        let w = b.transformed(&self.to_world);
        let pad = (w.min.abs().max(w.max.abs())) * 4.0 * f32::EPSILON;
        Aabb::new(w.min - pad, w.max + pad)
    }
}

/// The hit of a ray through instances: which instance, and the group's
/// primitive and barycentrics there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceHit {
    pub instance: u32,
    pub hit: MeshHit,
}

/// Groups, their instances and the top-level hierarchy over them.
#[derive(Clone, Debug, Default)]
pub struct Instances {
    pub groups: Vec<MeshAccel>,
    pub instances: Vec<Instance>,
    tlas: WideBvh,
    /// Each instance's world box (empty for an empty group).
    boxes: Vec<Aabb>,
}

impl Instances {
    /// The top-level hierarchy over `instances` of `groups`; an instance
    /// naming a group that does not exist is an error.
    pub fn new(groups: Vec<MeshAccel>, instances: Vec<Instance>) -> Result<Instances, String> {
        let group_boxes: Vec<Aabb> = groups.iter().map(finite_bounds).collect();
        let boxes = instances
            .iter()
            .enumerate()
            .map(|(i, inst)| {
                let b = group_boxes.get(inst.group as usize).ok_or_else(|| {
                    format!(
                        "instance {i}: there is no group {} ({} groups)",
                        inst.group,
                        groups.len()
                    )
                })?;
                Ok(if b.is_empty() { *b } else { inst.world_box(b) })
            })
            .collect::<Result<Vec<Aabb>, String>>()?;
        Ok(Instances {
            tlas: WideBvh::new(&boxes),
            groups,
            instances,
            boxes,
        })
    }

    /// The box of every instance (empty without any).
    pub fn bounds(&self) -> Aabb {
        union_of_finite(self.boxes.iter().copied())
    }

    /// Bytes of the groups, the instances (maps both ways and boxes) and
    /// the top-level hierarchy.
    pub fn memory_bytes(&self) -> usize {
        self.groups
            .iter()
            .map(MeshAccel::memory_bytes)
            .sum::<usize>()
            + self.instances.len() * (std::mem::size_of::<Instance>() + std::mem::size_of::<Aabb>())
            + self.tlas.memory_bytes()
    }

    /// Nodes of the top-level hierarchy.
    pub fn tlas(&self) -> &WideBvh {
        &self.tlas
    }

    /// The closest hit in `(0, t_max)` among the primitives `keep` accepts
    /// (by group and group primitive).
    pub fn intersect_where(
        &self,
        ray: &Ray,
        t_max: f32,
        keep: impl Fn(u32, u32) -> bool,
    ) -> Option<InstanceHit> {
        let mut best = None;
        self.tlas.closest_hit(ray, t_max, |slot, t_max| {
            let instance = self.tlas.order()[slot as usize];
            let inst = &self.instances[instance as usize];
            let local = inst.object_ray(ray);
            let g = inst.group;
            let hit = self.groups[g as usize].intersect_where(&local, t_max, |p| keep(g, p))?;
            best = Some(InstanceHit { instance, hit });
            Some(hit.hit.t)
        })?;
        best
    }

    /// Whether any primitive `keep` accepts lies on the ray in `(0, t_max)`.
    pub fn occluded_where(&self, ray: &Ray, t_max: f32, keep: impl Fn(u32, u32) -> bool) -> bool {
        self.tlas.any_hit(ray, t_max, |slot, t_max| {
            let inst = &self.instances[self.tlas.order()[slot as usize] as usize];
            let local = inst.object_ray(ray);
            let g = inst.group;
            self.groups[g as usize]
                .occluded_where(&local, t_max, |p| keep(g, p))
                .then_some(0.0)
        })
    }
}

/// The box of a group's primitives with finite boxes.
fn finite_bounds(accel: &MeshAccel) -> Aabb {
    union_of_finite(accel.primitive_bounds())
}

/// The union of the boxes that are neither empty nor infinite.
fn union_of_finite(boxes: impl IntoIterator<Item = Aabb>) -> Aabb {
    boxes
        .into_iter()
        .filter(|b| !b.is_empty() && b.min.is_finite() && b.max.is_finite())
        .fold(Aabb::EMPTY, Aabb::union)
}

#[cfg(test)]
mod instances_test {
    use super::*;
    use crate::analytic::{AnalyticShape, Quadric};
    use crate::shapes::uv_sphere;
    use crate::TriangleMesh;
    use fogbank_math::{DVec3, Pcg32};
    use glam::DQuat;

    /// A group's triangles and analytic shapes copied into the world under
    /// each instance's map: what the two-level hierarchy must answer alike.
    fn flattened(groups: &[MeshAccel], instances: &[Instance]) -> (MeshAccel, Vec<(u32, u32)>) {
        let mut mesh = TriangleMesh::default();
        let mut analytic = Vec::new();
        let (mut tri_of, mut ana_of) = (Vec::new(), Vec::new());
        for (i, inst) in instances.iter().enumerate() {
            let g = &groups[inst.group as usize];
            let v0 = mesh.positions.len() as u32;
            let m = glam::DMat4::from(inst.to_world).as_mat4();
            let mut copy = g.mesh.clone();
            copy.transform(&m);
            mesh.positions.extend(copy.positions);
            mesh.triangles
                .extend(copy.triangles.iter().map(|t| t.map(|v| v + v0)));
            tri_of.extend((0..g.mesh.len() as u32).map(|p| (i as u32, p)));
            for (k, a) in g.analytic.iter().enumerate() {
                let a2 = AnalyticShape::new(a.quadric, inst.to_world * a.to_world, a.flip);
                analytic.push(a2.expect("invertible"));
                ana_of.push((i as u32, (g.mesh.len() + k) as u32));
            }
        }
        tri_of.extend(ana_of);
        (MeshAccel::with_analytic(mesh, analytic), tri_of)
    }

    fn scene() -> (Vec<MeshAccel>, Vec<Instance>) {
        let bumpy = uv_sphere(12, |t, p| 1.0 + 0.2 * (3.0 * t).sin() * (4.0 * p).cos());
        let ball = AnalyticShape::new(
            Quadric::Sphere,
            DAffine3::from_scale(DVec3::splat(0.5)),
            false,
        )
        .unwrap();
        let disk = AnalyticShape::new(
            Quadric::Disk,
            DAffine3::from_translation(DVec3::new(0.0, 0.0, 1.5)),
            false,
        )
        .unwrap();
        let groups = vec![
            MeshAccel::new(bumpy),
            MeshAccel::with_analytic(TriangleMesh::default(), vec![ball, disk]),
            MeshAccel::new(TriangleMesh::default()),
        ];
        let mut rng = Pcg32::new(7, 3);
        let mut instances = Vec::new();
        for k in 0..60u32 {
            let mut r = || rng.next_f32() as f64;
            let t = DVec3::new(8.0 * r() - 4.0, 8.0 * r() - 4.0, 8.0 * r() - 4.0);
            let q = DQuat::from_axis_angle(DVec3::new(r(), r(), r() + 0.1).normalize(), 6.0 * r());
            // Non-uniform scales and, for every fifth, a mirror.
            let mut s = DVec3::new(0.3 + r(), 0.3 + r(), 0.3 + r());
            if k % 5 == 0 {
                s.x = -s.x;
            }
            let m = DAffine3::from_scale_rotation_translation(s, q, t);
            instances.push(Instance::new(k % 3, m).unwrap());
        }
        (groups, instances)
    }

    /// Closest and any hit through the instances equal the flattened
    /// copies' on random rays: same instance and primitive, same distance
    /// to rounding (the copies are rounded once more).
    #[test]
    fn instances_answer_as_their_flattened_copies() {
        let (groups, instances) = scene();
        let (flat, of) = flattened(&groups, &instances);
        let inst = Instances::new(groups, instances).unwrap();
        let mut rng = Pcg32::new(11, 5);
        let (mut hits, mut agree) = (0, 0);
        let n = 4000;
        for _ in 0..n {
            let mut r = || 2.0 * rng.next_f32() - 1.0;
            let o = Vec3::new(r(), r(), r()) * 6.0;
            // Toward the instances' cube.
            let d = Vec3::new(r(), r(), r()) * 4.0 - o;
            let ray = Ray::new(o, d);
            let a = inst.intersect_where(&ray, f32::INFINITY, |_, _| true);
            let b = flat.intersect(&ray, f32::INFINITY);
            assert_eq!(a.is_some(), b.is_some(), "ray {ray:?}");
            assert_eq!(
                inst.occluded_where(&ray, f32::INFINITY, |_, _| true),
                b.is_some()
            );
            if let (Some(a), Some(b)) = (a, b) {
                hits += 1;
                let rel = (a.hit.hit.t - b.hit.t).abs() / b.hit.t;
                assert!(rel < 1e-4, "t {} vs {}", a.hit.hit.t, b.hit.t);
                agree += ((a.instance, a.hit.primitive) == of[b.primitive as usize]) as u32;
                // Shorter than the hit: nothing in between.
                assert!(!inst.occluded_where(&ray, b.hit.t * 0.999, |_, _| true));
            }
        }
        assert!(hits > n / 4, "{hits} hits");
        // Ties between coincident copies aside, the same primitive.
        assert!(agree as f64 > 0.99 * hits as f64, "{agree} of {hits}");
    }

    #[test]
    fn keep_filters_by_group_and_bad_groups_are_refused() {
        let (groups, instances) = scene();
        let inst = Instances::new(groups.clone(), instances.clone()).unwrap();
        let ray = Ray::new(Vec3::new(-9.0, 0.1, 0.2), Vec3::X);
        if let Some(h) = inst.intersect_where(&ray, f32::INFINITY, |_, _| true) {
            let g = inst.instances[h.instance as usize].group;
            let other = inst.intersect_where(&ray, f32::INFINITY, |gg, _| gg != g);
            assert!(other.is_none_or(|o| inst.instances[o.instance as usize].group != g));
        }
        let bad = vec![Instance::new(3, DAffine3::IDENTITY).unwrap()];
        let e = Instances::new(groups, bad).unwrap_err();
        assert!(e.contains("no group 3"), "{e}");
        assert!(Instance::new(0, DAffine3::from_scale(DVec3::new(1.0, 0.0, 1.0))).is_none());
        assert!(Instances::default()
            .intersect_where(&ray, 1.0, |_, _| true)
            .is_none());
    }
}

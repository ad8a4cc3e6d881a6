//! Mitsuba 3's analytic shapes: the `sphere` (the unit sphere about the
//! origin) and the `disk` (the unit disk in the z = 0 plane facing +z),
//! each placed by an affine map, intersected exactly rather than
//! tessellated. The ray is carried into object space in f64 and the sphere's
//! quadratic uses the form of Haines et al. (Ray Tracing Gems, ch. 7) that
//! avoids the cancellation of b² − 4ac for distant or grazing rays. Hit
//! parameters (normals, UVs) follow Mitsuba 3's `sphere` and `disk`.

use fogbank_math::{Aabb, DAffine3, DVec3, Ray, Vec3};
use glam::Vec2;
use std::f64::consts::PI;

/// Which unit shape an [`AnalyticShape`] places.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quadric {
    Sphere = 0,
    Disk = 1,
}

impl Quadric {
    /// By id (the GPU's `QUADRIC_*`).
    pub const NAMES: [&'static str; 2] = ["sphere", "disk"];

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// A unit [`Quadric`] under an affine map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnalyticShape {
    pub quadric: Quadric,
    pub to_world: DAffine3,
    pub to_object: DAffine3,
    /// Normals point inward (sphere) or along −z (disk): Mitsuba's
    /// `flip_normals`.
    pub flip: bool,
}

/// What a hit on an analytic shape gives the shading code.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnalyticHit {
    /// On the surface (reprojected onto it, not o + t d).
    pub p: Vec3,
    /// Unit normal (flipped with `flip`); geometric and shading alike.
    pub n: Vec3,
    /// Mitsuba's parameterisation: sphere (φ/2π, θ/π), disk (r, φ/2π).
    pub uv: Vec2,
}

impl AnalyticShape {
    /// `None` when `to_world` or its inverse is not finite (not
    /// invertible, or so near singular that the inverse overflows).
    pub fn new(quadric: Quadric, to_world: DAffine3, flip: bool) -> Option<AnalyticShape> {
        let det = to_world.matrix3.determinant();
        if !(to_world.is_finite() && det != 0.0 && det.is_finite()) {
            return None;
        }
        let to_object = to_world.inverse();
        let shape = AnalyticShape {
            quadric,
            to_world,
            to_object,
            flip,
        };
        let b = shape.bounds();
        (to_object.is_finite() && b.min.is_finite() && b.max.is_finite()).then_some(shape)
    }

    /// The exact box: along world axis i the image of the unit ball
    /// reaches the length of row i of the linear map (of its first two
    /// columns for the disk, which has no z extent).
    pub fn bounds(&self) -> Aabb {
        let m = self.to_world.matrix3.transpose(); // rows as columns
        let rows = [m.x_axis, m.y_axis, m.z_axis];
        let reach = DVec3::from_array(rows.map(|r| match self.quadric {
            Quadric::Sphere => r.length(),
            Quadric::Disk => r.truncate().length(),
        }));
        let c = self.to_world.translation;
        Aabb::new((c - reach).as_vec3(), (c + reach).as_vec3())
    }

    fn object_ray(&self, ray: &Ray) -> (DVec3, DVec3) {
        (
            self.to_object.transform_point3(ray.o.as_dvec3()),
            self.to_object.transform_vector3(ray.d.as_dvec3()),
        )
    }

    /// The nearest hit in `(0, t_max)`: its ray parameter, which the affine
    /// map leaves unchanged (the object-space direction is not normalised).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let (o, d) = self.object_ray(ray);
        let t = match self.quadric {
            Quadric::Sphere => unit_sphere_t(o, d, t_max as f64),
            Quadric::Disk => unit_disk_t(o, d, t_max as f64),
        }?;
        Some(t as f32).filter(|t| *t > 0.0 && *t < t_max)
    }

    /// The surface data of the hit at `t` on `ray`.
    pub fn hit(&self, ray: &Ray, t: f32) -> AnalyticHit {
        let (o, d) = self.object_ray(ray);
        let mut local = o + t as f64 * d;
        let (n_object, uv) = match self.quadric {
            Quadric::Sphere => {
                local = local.normalize_or_zero();
                let theta = local.z.clamp(-1.0, 1.0).acos();
                (local, DVec3::new(azimuth(local), theta / PI, 0.0))
            }
            Quadric::Disk => {
                local.z = 0.0;
                let r = local.truncate().length();
                (DVec3::Z, DVec3::new(r, azimuth(local), 0.0))
            }
        };
        // Normals map by the inverse transpose.
        let n = self.to_object.matrix3.transpose() * n_object;
        let n = n.normalize_or_zero().as_vec3() * if self.flip { -1.0 } else { 1.0 };
        let p = self.to_world.transform_point3(local).as_vec3();
        AnalyticHit {
            p: if p.is_finite() { p } else { ray.at(t) },
            n,
            uv: Vec2::new(uv.x as f32, uv.y as f32),
        }
    }
}

/// φ/2π in [0, 1) of an object-space point.
fn azimuth(p: DVec3) -> f64 {
    let v = p.y.atan2(p.x) / (2.0 * PI);
    if v < 0.0 {
        v + 1.0
    } else {
        v
    }
}

/// The nearest root in `(0, t_max)` of |o + t d| = 1.
fn unit_sphere_t(o: DVec3, d: DVec3, t_max: f64) -> Option<f64> {
    let a = d.length_squared();
    if a == 0.0 {
        return None;
    }
    let b = -o.dot(d); // half of −B
                       // Δ/4 = a·(1 − |o + (b/a)d|²): the squared distance of the line from
                       // the centre, computed directly rather than as b² − ac.
    let perp = o + (b / a) * d;
    let disc = a * (1.0 - perp.length_squared());
    if disc < 0.0 {
        return None;
    }
    let q = b + b.signum() * disc.sqrt();
    let c = o.length_squared() - 1.0;
    let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q / a) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    [t0, t1].into_iter().find(|&t| t > 0.0 && t < t_max)
}

/// The hit of o + t d with the unit disk at z = 0 in `(0, t_max)`.
fn unit_disk_t(o: DVec3, d: DVec3, t_max: f64) -> Option<f64> {
    if d.z == 0.0 {
        return None;
    }
    let t = -o.z / d.z;
    if !(t > 0.0 && t < t_max) {
        return None;
    }
    let p = o + t * d;
    (p.x * p.x + p.y * p.y <= 1.0).then_some(t)
}

#[cfg(test)]
mod analytic_test {
    use super::*;
    use fogbank_math::Pcg32;

    fn sphere(centre: Vec3, r: f32) -> AnalyticShape {
        let m = DAffine3::from_scale_rotation_translation(
            DVec3::splat(r as f64),
            glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
            centre.as_dvec3(),
        );
        AnalyticShape::new(Quadric::Sphere, m, false).unwrap()
    }

    #[test]
    fn sphere_hits_lie_on_it_and_misses_pass_outside() {
        let mut rng = Pcg32::new(6, 1);
        let (c, r) = (Vec3::new(0.3, -0.2, 0.1), 0.7f32);
        let s = sphere(c, r);
        let (mut hits, mut inside) = (0, 0);
        for k in 0..20_000 {
            let mut u = || 2.0 * rng.next_f32() - 1.0;
            // Near and far origins (far: the cancellation case), some inside.
            let scale = if k % 4 == 0 { 1e4 } else { 2.0 };
            let o = c + Vec3::new(u(), u(), u()) * scale;
            let d = (c + Vec3::new(u(), u(), u()) * 0.5 - o).normalize()
                + Vec3::new(u(), u(), u()) * 0.3;
            let ray = Ray::new(o, d);
            let (o64, d64) = ((o - c).as_dvec3(), d.as_dvec3());
            let dist2 = (o64 - o64.dot(d64) / d64.length_squared() * d64).length_squared();
            let started_inside = (o - c).length() < r;
            match s.intersect(&ray, f32::INFINITY) {
                Some(t) => {
                    hits += 1;
                    let p = (o64 + t as f64 * d64).length();
                    assert!(
                        (p - r as f64).abs() < 1e-5 * scale as f64,
                        "ray {k}: |p| = {p}"
                    );
                    let h = s.hit(&ray, t);
                    assert!(((h.p - c).length() - r).abs() < 1e-5);
                    assert!((h.n - (h.p - c) / r).length() < 1e-4, "{h:?}");
                }
                None => assert!(
                    !started_inside && (dist2 >= (r * r) as f64 * 0.999 || o64.dot(d64) > 0.0),
                    "ray {k} missed at distance² {dist2}"
                ),
            }
            inside += started_inside as usize;
        }
        assert!(hits > 5000 && inside > 100, "{hits} hits, {inside} inside");
        // From inside: the exit; t_max before the exit: nothing.
        let s = sphere(Vec3::ZERO, 2.0);
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert!((s.intersect(&ray, f32::INFINITY).unwrap() - 2.0).abs() < 1e-6);
        assert_eq!(s.intersect(&ray, 1.5), None);
    }

    #[test]
    fn disk_hits_inside_its_ellipse_only() {
        // Stretched 2× along x, raised to z = 1, flipped.
        let m = DAffine3::from_scale_rotation_translation(
            DVec3::new(2.0, 1.0, 1.0),
            glam::DQuat::IDENTITY,
            DVec3::Z,
        );
        let d = AnalyticShape::new(Quadric::Disk, m, true).unwrap();
        let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 3.0), -Vec3::Z);
        assert_eq!(d.intersect(&down(1.5, 0.5), f32::INFINITY), Some(2.0));
        assert_eq!(d.intersect(&down(1.2, 0.9), f32::INFINITY), None);
        assert_eq!(d.intersect(&down(1.0, 0.0), 1.5), None);
        let side = Ray::new(Vec3::new(-3.0, 0.0, 1.0), Vec3::X);
        assert_eq!(d.intersect(&side, f32::INFINITY), None);
        let h = d.hit(&down(1.0, 1.0 / 3f32.sqrt()), 2.0);
        assert_eq!(h.n, -Vec3::Z);
        assert!((h.p - Vec3::new(1.0, 1.0 / 3f32.sqrt(), 1.0)).length() < 1e-6);
        // Object point (0.5, 0.577): r = 0.764, φ = 49.1°.
        let r = (0.25f32 + 1.0 / 3.0).sqrt();
        let phi = (1.0 / 3f32.sqrt()).atan2(0.5) / (2.0 * std::f32::consts::PI);
        assert!((h.uv - Vec2::new(r, phi)).length() < 1e-6, "{:?}", h.uv);
    }

    #[test]
    fn boxes_are_tight() {
        let s = sphere(Vec3::new(1.0, 2.0, 3.0), 0.5);
        let b = s.bounds();
        assert!((b.min - Vec3::new(0.5, 1.5, 2.5)).length() < 1e-6, "{b:?}");
        assert!((b.max - Vec3::new(1.5, 2.5, 3.5)).length() < 1e-6, "{b:?}");
        // A disk tilted 90° about x spans y = 0 and x, z in [−1, 1].
        let m = DAffine3::from_rotation_x(std::f64::consts::FRAC_PI_2);
        let b = AnalyticShape::new(Quadric::Disk, m, false)
            .unwrap()
            .bounds();
        assert!(
            (b.min - Vec3::new(-1.0, 0.0, -1.0)).abs().max_element() < 1e-6,
            "{b:?}"
        );
        assert!(
            (b.max - Vec3::new(1.0, 0.0, 1.0)).abs().max_element() < 1e-6,
            "{b:?}"
        );
        // The sphere's uv at the +y pole of the equator: φ = 90°, θ = 90°.
        let unit = AnalyticShape::new(Quadric::Sphere, DAffine3::IDENTITY, false).unwrap();
        let h = unit.hit(&Ray::new(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y), 2.0);
        assert!((h.uv - Vec2::new(0.25, 0.5)).length() < 1e-6, "{:?}", h.uv);
        assert!(AnalyticShape::new(Quadric::Disk, DAffine3::ZERO, false).is_none());
        let huge = DAffine3::from_scale(DVec3::splat(1e39));
        assert!(AnalyticShape::new(Quadric::Sphere, huge, false).is_none());
    }
}

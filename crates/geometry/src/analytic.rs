//! Mitsuba 3's analytic shapes in object space: the `sphere` (centre 0,
//! radius r; Mitsuba's `center`/`radius` become the scene transform) and
//! the `disk` (unit disk in the z = 0 plane facing +z). The sphere's
//! quadratic uses the form of Haines et al. (Ray Tracing Gems, ch. 7) that
//! avoids the cancellation of b² − 4ac for distant or grazing rays.

use fogbank_math::{Ray, Vec3};

/// The nearest hit of `ray` with the sphere of radius `r` about the
/// origin in `(0, t_max)`.
pub fn intersect_sphere(ray: &Ray, r: f32, t_max: f32) -> Option<f32> {
    // In f64: the terms below are small differences of large numbers when
    // the origin is far from the sphere.
    let (o, d) = (ray.o.as_dvec3(), ray.d.as_dvec3());
    let r = r as f64;
    let a = d.length_squared();
    if a == 0.0 {
        return None;
    }
    let b = -o.dot(d); // half of −B
                       // Δ/4 = a·(r² − |o + (b/a)d|²): the squared distance of the line from
                       // the centre, computed directly.
    let perp = o + (b / a) * d;
    let disc = a * (r * r - perp.length_squared());
    if disc < 0.0 {
        return None;
    }
    let q = b + b.signum() * disc.sqrt();
    let c = o.length_squared() - r * r;
    let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q / a) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    [t0, t1]
        .into_iter()
        .find(|&t| t > 0.0 && t < t_max as f64)
        .map(|t| t as f32)
        .filter(|t| *t > 0.0)
}

/// The hit of `ray` with the unit disk at z = 0 in `(0, t_max)`.
pub fn intersect_disk(ray: &Ray, t_max: f32) -> Option<f32> {
    if ray.d.z == 0.0 {
        return None;
    }
    let t = -ray.o.z / ray.d.z;
    if !(t > 0.0 && t < t_max) {
        return None;
    }
    let p = ray.at(t);
    (p.x * p.x + p.y * p.y <= 1.0).then_some(t)
}

/// The outward normal of the sphere at object-space point `p`.
pub fn sphere_normal(p: Vec3) -> Vec3 {
    p.normalize_or_zero()
}

#[cfg(test)]
mod analytic_test {
    use super::*;
    use fogbank_math::Pcg32;

    #[test]
    fn sphere_hits_lie_on_it_and_misses_pass_outside() {
        let mut rng = Pcg32::new(6, 1);
        let r = 0.7f32;
        let (mut hits, mut inside) = (0, 0);
        for k in 0..20_000 {
            let mut u = || 2.0 * rng.next_f32() - 1.0;
            // Near and far origins (far: the cancellation case), some inside.
            let scale = if k % 4 == 0 { 1e4 } else { 2.0 };
            let o = Vec3::new(u(), u(), u()) * scale;
            let d =
                (Vec3::new(u(), u(), u()) * 0.5 - o).normalize() + Vec3::new(u(), u(), u()) * 0.3;
            let ray = Ray::new(o, d);
            let (o64, d64) = (o.as_dvec3(), d.as_dvec3());
            let dist2 = (o64 - o64.dot(d64) / d64.length_squared() * d64).length_squared();
            let started_inside = o.length() < r;
            match intersect_sphere(&ray, r, f32::INFINITY) {
                Some(t) => {
                    hits += 1;
                    let p = (o64 + t as f64 * d64).length();
                    assert!(
                        (p - r as f64).abs() < 1e-5 * scale as f64,
                        "ray {k}: |p| = {p}"
                    );
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
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(intersect_sphere(&ray, 2.0, f32::INFINITY), Some(2.0));
        assert_eq!(intersect_sphere(&ray, 2.0, 1.5), None);
    }

    #[test]
    fn disk_hits_inside_the_unit_circle_only() {
        let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z);
        assert_eq!(intersect_disk(&down(0.5, 0.5), f32::INFINITY), Some(1.0));
        assert_eq!(intersect_disk(&down(0.8, 0.8), f32::INFINITY), None);
        assert_eq!(
            intersect_disk(&Ray::new(Vec3::Z, Vec3::X), f32::INFINITY),
            None
        );
        assert_eq!(intersect_disk(&down(0.0, 0.0), 0.5), None);
    }
}

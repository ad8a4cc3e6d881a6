//! Watertight ray–triangle intersection (Woop, Benthin and Wald 2013, as in
//! pbrt-v4 §6.5.3): the vertices are moved into a frame where the ray runs
//! along +z from the origin, and the hit is decided by the signs of three
//! edge functions. A ray through a shared edge or vertex hits one of the
//! triangles around it — never none of them, the cracks that make media
//! leak through closed meshes — and edge functions that round to zero are
//! recomputed in double precision.

use fogbank_math::{Ray, Vec3};

/// Where a ray meets a triangle: the ray parameter and the barycentric
/// coordinates of vertices 1 and 2 (vertex 0's is `1 − b1 − b2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// The ray's frame: the index of its largest direction component (which
/// becomes z) and the shear that maps the direction onto +z. Computed once
/// per ray, shared by every triangle it is tested against.
#[derive(Clone, Copy, Debug)]
pub struct RayFrame {
    o: Vec3,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

impl RayFrame {
    pub fn new(ray: &Ray) -> RayFrame {
        let a = ray.d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        // Keep the frame right-handed so the edge functions' sign means the
        // same for every permutation.
        if ray.d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let dz = ray.d[kz];
        RayFrame {
            o: ray.o,
            kx,
            ky,
            kz,
            sx: -ray.d[kx] / dz,
            sy: -ray.d[ky] / dz,
            sz: 1.0 / dz,
        }
    }

    /// A vertex in the ray's sheared frame (z not yet scaled by `sz`).
    #[inline]
    fn shear(&self, p: Vec3) -> (f32, f32, f32) {
        let q = p - self.o;
        let (x, y, z) = (q[self.kx], q[self.ky], q[self.kz]);
        (x + self.sx * z, y + self.sy * z, z)
    }
}

/// The hit of `ray` (via its `frame`) with triangle (p0, p1, p2) strictly
/// inside `(0, t_max)`, or `None`. Degenerate and NaN triangles never hit.
#[inline]
pub fn intersect(
    frame: &RayFrame,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    t_max: f32,
) -> Option<TriangleHit> {
    let (x0, y0, z0) = frame.shear(p0);
    let (x1, y1, z1) = frame.shear(p1);
    let (x2, y2, z2) = frame.shear(p2);
    let mut e0 = x1 * y2 - y1 * x2;
    let mut e1 = x2 * y0 - y2 * x0;
    let mut e2 = x0 * y1 - y0 * x1;
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let d = |ax: f32, ay: f32, bx: f32, by: f32| {
            (ax as f64 * by as f64 - ay as f64 * bx as f64) as f32
        };
        e0 = d(x1, y1, x2, y2);
        e1 = d(x2, y2, x0, y0);
        e2 = d(x0, y0, x1, y1);
    }
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    // Zero (edge-on or degenerate) or NaN: no hit.
    if det.is_nan() || det == 0.0 {
        return None;
    }
    let (z0, z1, z2) = (z0 * frame.sz, z1 * frame.sz, z2 * frame.sz);
    let t_scaled = e0 * z0 + e1 * z1 + e2 * z2;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inv = 1.0 / det;
    let (b1, b2) = (e1 * inv, e2 * inv);
    let t = t_scaled * inv;
    // pbrt-v4's conservative bound on t's rounding error: reject hits whose
    // t is not certainly positive.
    let max_z = z0.abs().max(z1.abs()).max(z2.abs());
    let delta_z = gamma(3) * max_z;
    let max_x = x0.abs().max(x1.abs()).max(x2.abs());
    let max_y = y0.abs().max(y1.abs()).max(y2.abs());
    let delta_x = gamma(5) * (max_x + max_z);
    let delta_y = gamma(5) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = e0.abs().max(e1.abs()).max(e2.abs());
    let delta_t = 3.0 * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv.abs();
    if t <= delta_t {
        return None;
    }
    if !(t.is_finite() && b1.is_finite() && b2.is_finite()) {
        return None;
    }
    Some(TriangleHit { t, b1, b2 })
}

/// γ_n = nε / (1 − nε), the rounding-error bound of n floating-point
/// operations (pbrt-v4 §6.8.1).
#[inline]
fn gamma(n: u32) -> f32 {
    let e = f32::EPSILON * 0.5;
    n as f32 * e / (1.0 - n as f32 * e)
}

#[cfg(test)]
mod triangle_test {
    use super::*;
    use fogbank_math::Pcg32;

    fn hit(o: Vec3, d: Vec3, p: [Vec3; 3]) -> Option<TriangleHit> {
        intersect(
            &RayFrame::new(&Ray::new(o, d)),
            p[0],
            p[1],
            p[2],
            f32::INFINITY,
        )
    }

    #[test]
    fn hits_inside_misses_outside_and_reports_barycentrics() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let h = hit(Vec3::new(0.25, 0.5, 2.0), -Vec3::Z, tri).unwrap();
        assert!((h.t - 2.0).abs() < 1e-6);
        assert!((h.b1 - 0.25).abs() < 1e-6 && (h.b2 - 0.5).abs() < 1e-6);
        // Both faces hit (no culling), any direction component dominant.
        assert!(hit(Vec3::new(0.2, 0.2, -3.0), Vec3::Z, tri).is_some());
        assert!(hit(Vec3::new(0.6, 0.6, 1.0), -Vec3::Z, tri).is_none());
        // Behind the origin, beyond t_max, edge-on, degenerate, NaN.
        assert!(hit(Vec3::new(0.2, 0.2, 1.0), Vec3::Z, tri).is_none());
        let f = RayFrame::new(&Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z));
        assert!(intersect(&f, tri[0], tri[1], tri[2], 0.5).is_none());
        assert!(hit(Vec3::new(-1.0, 0.2, 0.0), Vec3::X, tri).is_none());
        assert!(hit(
            Vec3::new(0.2, 0.2, 1.0),
            -Vec3::Z,
            [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X]
        )
        .is_none());
        assert!(hit(
            Vec3::new(0.2, 0.2, 1.0),
            -Vec3::Z,
            [Vec3::NAN, Vec3::X, Vec3::Y]
        )
        .is_none());
    }

    /// Rays through the shared edge and vertex of a fan of triangles hit
    /// exactly one or more of them, never none: no cracks.
    #[test]
    fn watertight_on_shared_edges_and_vertices() {
        // A fan of 8 triangles around the origin in the z = 0 plane.
        let n = 8;
        let ring: Vec<Vec3> = (0..n)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / n as f32;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let tris: Vec<[Vec3; 3]> = (0..n)
            .map(|i| [Vec3::ZERO, ring[i], ring[(i + 1) % n]])
            .collect();
        let mut rng = Pcg32::new(7, 1);
        for k in 0..20_000 {
            // Aim at a point on a shared edge (or at the centre vertex).
            let i = k % n;
            let s = if k % 5 == 0 {
                0.0
            } else {
                rng.next_f32() * 0.999
            };
            let target = ring[i] * s;
            let o = Vec3::new(
                rng.next_f32() - 0.5,
                rng.next_f32() - 0.5,
                1.0 + rng.next_f32(),
            ) * 3.0;
            let d = target - o;
            let hits = tris.iter().filter(|t| hit(o, d, **t).is_some()).count();
            assert!(hits >= 1, "ray {k} through {target:?} slipped through");
        }
    }
}

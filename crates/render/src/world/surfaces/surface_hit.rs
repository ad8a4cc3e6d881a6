//! What a surface hit gives the integrators ([`SurfaceHit`]), worked out
//! from a BVH hit in the space of the mesh that was hit, and the built
//! [`Shape`] it belongs to.

use super::material::Material;
use fogbank_geometry::{MeshAccel, MeshHit};
use fogbank_math::{Ray, Vec3};
use glam::Vec2;

/// A built shape: its material and emission, and where its primitives
/// (its triangles, or its one analytic shape) and (when it emits) its
/// lights sit in the scene's arrays.
#[derive(Clone, Debug)]
pub struct Shape {
    pub material: Material,
    pub emission: Option<Vec3>,
    /// Its first primitive (the BVH's index: triangles, then analytic
    /// shapes; of its group's BVH for a shape of a group).
    pub first_triangle: u32,
    /// Index in `World::lights` of the light of `first_triangle` (the
    /// shape's triangles' lights follow in order; degenerate triangles get
    /// a zero-radiance light so the indices stay aligned).
    pub first_light: u32,
    /// World media inside (behind the normals) and outside.
    pub interior: Option<usize>,
    pub exterior: Option<usize>,
    pub(super) has_normals: bool,
    pub(super) has_uvs: bool,
    /// An analytic sphere or disk (one primitive, after the triangles).
    pub(super) analytic: bool,
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
    /// The triangle or analytic shape hit (the BVH's primitive index; its
    /// group's for a shape of a group, which never emits).
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

/// The shading data of hit `h` of `ray` on `accel`'s primitive, whose
/// shapes `shape_of` gives (in the space of `accel` and `ray`).
pub(super) fn surface_hit(
    accel: &MeshAccel,
    shape_of: &[u32],
    shapes: &[Shape],
    ray: &Ray,
    h: MeshHit,
) -> SurfaceHit {
    let shape = shape_of[h.primitive as usize];
    if let Some(a) = accel.analytic_of(h.primitive) {
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
    let s = &shapes[shape as usize];
    let m = &accel.mesh;
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

//! Bounds of a set of one-sided emitters for the light BVH, after Conty
//! Estevez & Kulla (2018) as pbrt-v4's `LightBounds` defines them: a box
//! holding the emitters, their summed power φ and a cone holding their
//! normals (axis `w`, half-angle θ_o; emission leaves within θ_e = π/2 of
//! a normal, as from one side of a Lambertian triangle). From these an
//! importance at a receiving point that is zero only where no emitter of
//! the set can deliver light.

use fogbank_math::Vec3;
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    pub min: Vec3,
    pub max: Vec3,
    /// Summed power of the emitters (the light selection's proxy).
    pub phi: f32,
    /// Unit axis of the normal cone.
    pub w: Vec3,
    /// cos θ_o (−1: normals in every direction).
    pub cos_theta_o: f32,
}

/// Widening of a merged normal cone (radians), so that rounding never
/// leaves a child's normal outside its parent's cone.
const CONE_SLACK: f32 = 1e-4;

/// cos and sin of max(0, θ_a − θ_b) from those of θ_a and θ_b.
fn sub_clamped((cos_a, sin_a): (f32, f32), (cos_b, sin_b): (f32, f32)) -> (f32, f32) {
    if cos_a > cos_b {
        (1.0, 0.0)
    } else {
        (cos_a * cos_b + sin_a * sin_b, sin_a * cos_b - cos_a * sin_b)
    }
}

fn sin_of(cos: f32) -> f32 {
    (1.0 - cos * cos).max(0.0).sqrt()
}

impl LightBounds {
    /// One emitting triangle with unit normal `n` and power `phi`.
    pub fn triangle(p: [Vec3; 3], n: Vec3, phi: f32) -> LightBounds {
        LightBounds {
            min: p[0].min(p[1]).min(p[2]),
            max: p[0].max(p[1]).max(p[2]),
            phi,
            w: n,
            cos_theta_o: 1.0,
        }
    }

    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// The bounds of both sets.
    pub fn union(&self, o: &LightBounds) -> LightBounds {
        let (w, cos_theta_o) = cone_union((self.w, self.cos_theta_o), (o.w, o.cos_theta_o));
        LightBounds {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
            phi: self.phi + o.phi,
            w,
            cos_theta_o,
        }
    }

    /// [`Importance::of`] these bounds at `p`.
    pub fn importance(&self, p: Vec3) -> f32 {
        Importance::from(self).of(p)
    }

    /// The orientation measure M_Ω of the cone with θ_e = π/2 (pbrt-v4's
    /// split cost, Conty Estevez & Kulla Eq. 1).
    pub fn measure(&self) -> f32 {
        let theta_o = self.cos_theta_o.clamp(-1.0, 1.0).acos();
        let theta_w = (theta_o + 0.5 * PI).min(PI);
        let sin_o = theta_o.sin();
        2.0 * PI * (1.0 - self.cos_theta_o)
            + 0.5
                * PI
                * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o
                    + self.cos_theta_o)
    }
}

/// What [`Importance::of`] reads of a [`LightBounds`], computed once per
/// node: the tree evaluates two nodes per level of every pick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Importance {
    pub centre: Vec3,
    pub phi: f32,
    pub w: Vec3,
    pub cos_theta_o: f32,
    /// Radius² of the sphere around the box.
    pub r2: f32,
    /// The lower clamp of d²: half the box diagonal.
    pub d2_min: f32,
    pub sin_theta_o: f32,
}

impl From<&LightBounds> for Importance {
    fn from(b: &LightBounds) -> Importance {
        let diagonal = b.max - b.min;
        Importance {
            centre: b.centroid(),
            phi: b.phi,
            w: b.w,
            cos_theta_o: b.cos_theta_o,
            r2: 0.25 * diagonal.length_squared(),
            d2_min: 0.5 * diagonal.length(),
            sin_theta_o: sin_of(b.cos_theta_o),
        }
    }
}

impl Importance {
    /// How much the set may light the point `p` (pbrt-v4's
    /// `LightBounds::Importance` for a point in a medium): φ cos θ' / d²,
    /// θ' the smallest angle between a normal of the cone and a direction
    /// from the box toward `p`; zero when that angle exceeds θ_e = π/2.
    /// d² is clamped below by half the box diagonal, so points near or
    /// inside the box do not blow up.
    pub fn of(&self, p: Vec3) -> f32 {
        let to_p = p - self.centre;
        let d2_centre = to_p.length_squared();
        let d2 = d2_centre.max(self.d2_min);
        // From inside the sphere around the box every direction leaves
        // the box, so nothing bounds θ'.
        if d2_centre <= self.r2 {
            return self.phi / d2;
        }
        let cos_w = self.w.dot(to_p / d2_centre.sqrt());
        let sin2_b = self.r2 / d2_centre;
        let cos_b = (1.0 - sin2_b).max(0.0).sqrt();
        let theta_x = sub_clamped((cos_w, sin_of(cos_w)), (self.cos_theta_o, self.sin_theta_o));
        let (cos_p, _) = sub_clamped(theta_x, (cos_b, sin2_b.sqrt()));
        if cos_p <= 0.0 {
            return 0.0;
        }
        (self.phi * cos_p / d2).max(0.0)
    }
}

/// The narrowest cone (axis, cos of half-angle) holding cones `a` and `b`.
fn cone_union(a: (Vec3, f32), b: (Vec3, f32)) -> (Vec3, f32) {
    let theta_a = a.1.clamp(-1.0, 1.0).acos();
    let theta_b = b.1.clamp(-1.0, 1.0).acos();
    // Angle between the axes, accurate for nearly equal ones.
    let theta_d = 2.0 * (0.5 * (a.0 - b.0).length()).min(1.0).asin();
    if (theta_d + theta_b).min(PI) <= theta_a {
        return a;
    }
    if (theta_d + theta_a).min(PI) <= theta_b {
        return b;
    }
    let theta_o = 0.5 * (theta_a + theta_d + theta_b) + CONE_SLACK;
    let axis = a.0.cross(b.0);
    if theta_o >= PI || axis.length_squared() == 0.0 {
        return (a.0, -1.0);
    }
    // Rotate a's axis toward b's by θ_o − θ_a about their common normal.
    let k = axis.normalize();
    let theta_r = theta_o - theta_a;
    let w = (a.0 * theta_r.cos() + k.cross(a.0) * theta_r.sin()).normalize();
    (w, theta_o.cos())
}

#[cfg(test)]
pub(crate) mod light_bounds_test {
    use super::*;
    use fogbank_math::Pcg32;

    pub(crate) fn unit(rng: &mut Pcg32) -> Vec3 {
        fogbank_math::warp::uniform_sphere([rng.next_f32(), rng.next_f32()])
    }

    #[test]
    fn merged_cones_hold_both_cones() {
        let mut rng = Pcg32::new(3, 4);
        for _ in 0..2000 {
            let a = (unit(&mut rng), rng.next_f32() * 2.0 - 1.0);
            let b = (unit(&mut rng), rng.next_f32() * 2.0 - 1.0);
            let (w, c) = cone_union(a, b);
            assert!((w.length() - 1.0).abs() < 1e-5);
            // Each child cone's farthest direction from the merged axis.
            for (axis, cos) in [a, b] {
                let reach = 2.0 * (0.5 * (axis - w).length()).min(1.0).asin() + cos.acos();
                assert!(
                    reach <= c.acos() + 2e-4 || c == -1.0,
                    "{a:?} {b:?} → {w} {c}: reach {reach} of {axis} {cos}"
                );
            }
        }
    }

    #[test]
    fn importance_is_zero_only_behind_every_emitter_and_finite() {
        // Triangles facing +z in the unit square at z = 0: points below the
        // plane get nothing, points above something.
        let mut rng = Pcg32::new(5, 6);
        let mut set: Option<LightBounds> = None;
        for _ in 0..20 {
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), 0.0);
            let t = LightBounds::triangle(
                [
                    o,
                    o + Vec3::new(0.05, 0.0, 0.0),
                    o + Vec3::new(0.0, 0.05, 0.0),
                ],
                Vec3::Z,
                1.0,
            );
            set = Some(set.map_or(t, |s| s.union(&t)));
        }
        let set = set.unwrap();
        assert_eq!(set.cos_theta_o, 1.0);
        for _ in 0..1000 {
            let p = 4.0 * unit(&mut rng) + Vec3::new(0.5, 0.5, 0.0);
            let i = set.importance(p);
            assert!(i.is_finite() && i >= 0.0);
            if p.z > 0.01 {
                assert!(i > 0.0, "{p}");
            }
        }
        // Far below, the bound is tight enough to exclude the set.
        assert_eq!(set.importance(Vec3::new(0.5, 0.5, -3.0)), 0.0);
        assert!(set.importance(Vec3::new(0.5, 0.5, 3.0)) > 0.0);
        // The measure of a single direction is π (cosine-weighted
        // hemisphere), of the whole sphere 4π + π/2·(…) = 4π.
        assert!((set.measure() - PI).abs() < 1e-4, "{}", set.measure());
        let all = LightBounds {
            cos_theta_o: -1.0,
            ..set
        };
        assert!((all.measure() - 4.0 * PI).abs() < 1e-3, "{}", all.measure());
    }
}

//! Axis-aligned boxes and a slab test that is robust for axis-parallel rays
//! and rays starting inside or on a face.

use crate::Ray;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Aabb { min, max }
    }

    /// The box that holds nothing; the identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    /// The smallest box holding both.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb::new(self.min.min(other.min), self.max.max(other.max))
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// The box holding this one's image under `m` (its eight corners
    /// mapped, in f64); empty stays empty.
    pub fn transformed(&self, m: &glam::DAffine3) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        (0..8).fold(Aabb::EMPTY, |b, k| {
            let pick = |i: usize| match k >> i & 1 {
                0 => self.min[i],
                _ => self.max[i],
            };
            let c = glam::DVec3::new(pick(0) as f64, pick(1) as f64, pick(2) as f64);
            let p = m.transform_point3(c).as_vec3();
            b.union(Aabb::new(p, p))
        })
    }

    /// Parameter interval `[t0, t1]` ∩ `[t_lo, t_hi]` where the ray is inside
    /// the closed box, or `None`. Axis-parallel components are handled without
    /// dividing by zero, so `0 · ∞ = NaN` never enters the comparison.
    pub fn intersect(&self, ray: &Ray, t_lo: f32, t_hi: f32) -> Option<(f32, f32)> {
        let mut t0 = t_lo;
        let mut t1 = t_hi;
        for a in 0..3 {
            let (o, d) = (ray.o[a], ray.d[a]);
            if d == 0.0 {
                if o < self.min[a] || o > self.max[a] {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d;
            let mut ta = (self.min[a] - o) * inv;
            let mut tb = (self.max[a] - o) * inv;
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            t0 = t0.max(ta);
            t1 = t1.min(tb);
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }
}

#[cfg(test)]
mod bbox_test {
    use super::*;

    #[test]
    fn axis_parallel_and_inside_rays() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let r = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        assert_eq!(b.intersect(&r, 0.0, f32::INFINITY), Some((1.0, 2.0)));
        let inside = Ray::new(Vec3::splat(0.5), Vec3::X);
        assert_eq!(b.intersect(&inside, 0.0, f32::INFINITY), Some((0.0, 0.5)));
        let grazing = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z);
        assert_eq!(b.intersect(&grazing, 0.0, 10.0), Some((1.0, 2.0)));
        let miss = Ray::new(Vec3::new(1.5, 0.5, -1.0), Vec3::Z);
        assert_eq!(b.intersect(&miss, 0.0, 10.0), None);
    }
}

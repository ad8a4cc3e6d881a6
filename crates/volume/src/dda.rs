//! Amanatides–Woo traversal of a uniform grid in index space.
//!
//! Each step's exit parameter is recomputed from the ray rather than
//! accumulated, so long traversals do not drift; axis-parallel rays never
//! step along their zero axes; a start on a face or slightly outside (from
//! rounding in the box clip) is clamped into the grid.

use crate::access::floor_i32;
use fogbank_math::Ray;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DdaStep {
    pub cell: [i32; 3],
    pub t0: f32,
    pub t1: f32,
}

#[derive(Clone, Debug)]
pub struct Dda {
    cell: [i32; 3],
    step: [i32; 3],
    n: [i32; 3],
    origin: [f32; 3],
    inv_d: [f32; 3],
    t_next: [f32; 3],
    cell_size: f32,
    t: f32,
    t_end: f32,
}

impl Dda {
    /// Traverses cells of edge `cell_size` covering `[0, n·cell_size]` along
    /// `ray` for `t ∈ [t0, t1]`; the caller clips `[t0, t1]` to that box.
    pub fn new(ray: &Ray, cell_size: f32, n: [u32; 3], t0: f32, t1: f32) -> Self {
        let n = n.map(|v| v as i32);
        let p = ray.at(t0);
        let mut cell = [0; 3];
        let mut step = [0; 3];
        let mut inv_d = [0.0; 3];
        let mut t_next = [f32::INFINITY; 3];
        for a in 0..3 {
            cell[a] = floor_i32(p[a] / cell_size).clamp(0, n[a] - 1);
            let d = ray.d[a];
            if d > 0.0 {
                step[a] = 1;
            } else if d < 0.0 {
                step[a] = -1;
            }
            if step[a] != 0 {
                inv_d[a] = 1.0 / d;
                let boundary = (cell[a] + (step[a] > 0) as i32) as f32 * cell_size;
                t_next[a] = (boundary - ray.o[a]) * inv_d[a];
            }
        }
        Dda {
            cell,
            step,
            n,
            origin: ray.o.to_array(),
            inv_d,
            t_next,
            cell_size,
            t: t0,
            t_end: t1,
        }
    }
}

impl Iterator for Dda {
    type Item = DdaStep;

    #[inline]
    fn next(&mut self) -> Option<DdaStep> {
        if self.t >= self.t_end {
            return None;
        }
        let a = if self.t_next[0] < self.t_next[1] {
            if self.t_next[0] < self.t_next[2] {
                0
            } else {
                2
            }
        } else if self.t_next[1] < self.t_next[2] {
            1
        } else {
            2
        };
        let t1 = self.t_next[a].min(self.t_end).max(self.t);
        let out = DdaStep {
            cell: self.cell,
            t0: self.t,
            t1,
        };
        self.t = t1;
        self.cell[a] += self.step[a];
        if self.cell[a] < 0 || self.cell[a] >= self.n[a] {
            self.t = self.t_end;
        } else {
            let boundary = (self.cell[a] + (self.step[a] > 0) as i32) as f32 * self.cell_size;
            self.t_next[a] = (boundary - self.origin[a]) * self.inv_d[a];
        }
        Some(out)
    }
}

#[cfg(test)]
mod dda_test {
    use super::*;
    use fogbank_math::{Aabb, Pcg32, Vec3};

    fn traverse(ray: &Ray, cs: f32, n: [u32; 3]) -> Vec<DdaStep> {
        let b = Aabb::new(
            Vec3::ZERO,
            Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32) * cs,
        );
        match b.intersect(ray, 0.0, f32::INFINITY) {
            Some((t0, t1)) => Dda::new(ray, cs, n, t0, t1).collect(),
            None => vec![],
        }
    }

    #[test]
    fn steps_are_contiguous_and_cover_the_clip() {
        let mut rng = Pcg32::new(7, 1);
        let n = [7, 5, 9];
        for _ in 0..2000 {
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 40.0
                - Vec3::splat(10.0);
            let mut d =
                Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - Vec3::splat(0.5);
            // Make a third of the rays axis-parallel in some component.
            let pick = rng.next_u32() % 6;
            if pick < 3 {
                d[pick as usize] = 0.0;
            }
            if d.length() == 0.0 {
                continue;
            }
            let ray = Ray::new(o, d);
            let b = Aabb::new(Vec3::ZERO, Vec3::new(14.0, 10.0, 18.0));
            let steps = traverse(&ray, 2.0, n);
            if let Some((t0, t1)) = b.intersect(&ray, 0.0, f32::INFINITY) {
                if t1 - t0 < 1e-4 {
                    continue;
                }
                assert!(!steps.is_empty());
                assert_eq!(steps[0].t0, t0);
                assert!((steps.last().unwrap().t1 - t1).abs() <= 1e-4 * t1.abs().max(1.0));
                for w in steps.windows(2) {
                    assert_eq!(w[0].t1, w[1].t0);
                    let moved: i32 = (0..3).map(|a| (w[0].cell[a] - w[1].cell[a]).abs()).sum();
                    assert_eq!(moved, 1);
                }
                for s in &steps {
                    let mid = ray.at(0.5 * (s.t0 + s.t1));
                    if s.t1 - s.t0 > 1e-3 {
                        for a in 0..3 {
                            let c = (mid[a] / 2.0).floor() as i32;
                            assert_eq!(c.clamp(0, n[a] as i32 - 1), s.cell[a]);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn grazing_face_and_inside_start() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z);
        let steps = traverse(&ray, 1.0, [4, 4, 4]);
        assert_eq!(steps.len(), 4);
        assert!(steps.iter().all(|s| s.cell[0] == 0 && s.cell[1] == 0));
        let inside = Ray::new(Vec3::new(2.5, 2.5, 2.5), Vec3::new(-1.0, 0.0, 0.0));
        let steps = traverse(&inside, 1.0, [4, 4, 4]);
        assert_eq!(
            steps.iter().map(|s| s.cell[0]).collect::<Vec<_>>(),
            vec![2, 1, 0]
        );
        assert_eq!(steps[0].t0, 0.0);
    }
}

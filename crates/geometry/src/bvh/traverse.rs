//! Stack traversal of the flat node array, nearer child first: closest hit
//! (shrinking `t_max` as hits are found) and any hit (stop at the first).
//! The primitive test is a closure, so meshes, analytic shapes and tests
//! against brute force share one traversal; the WGSL mirror reads the same
//! nodes.

use super::node::Bvh;
use fogbank_math::{Ray, Vec3};

const STACK: usize = 64;

/// A ray prepared for box tests: origin and reciprocal direction, and the
/// rounding allowance that keeps a box containing a hit from being missed.
pub(super) struct Traversal {
    o: Vec3,
    inv_d: Vec3,
}

/// 1 + 2γ₃ (pbrt-v4 §6.8.2): the far slab distance grows by this factor.
const SLAB_GROW: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

impl Traversal {
    fn new(ray: &Ray) -> Traversal {
        Traversal {
            o: ray.o,
            inv_d: Vec3::ONE / ray.d,
        }
    }

    /// Entry distance of the ray into the box within `(0, t_max)`, or None.
    /// Axis-parallel rays make `0 · ∞ = NaN` slab distances; `f32::max` and
    /// `min` skip NaN, so such an axis constrains nothing.
    #[inline]
    fn enter(&self, min: [f32; 3], max: [f32; 3], t_max: f32) -> Option<f32> {
        let (mut t0, mut t1) = (0.0f32, t_max);
        for a in 0..3 {
            let ta = (min[a] - self.o[a]) * self.inv_d[a];
            let tb = (max[a] - self.o[a]) * self.inv_d[a];
            let (near, far) = if ta > tb { (tb, ta) } else { (ta, tb) };
            t0 = t0.max(near);
            t1 = t1.min(far * SLAB_GROW);
        }
        (t0 <= t1).then_some(t0)
    }
}

impl Bvh {
    /// The closest hit in `(0, t_max)`: `test(slot, t_max)` returns the hit
    /// distance of the primitive in leaf slot `slot` (primitive
    /// `order[slot]`) if it is below `t_max`. Returns the slot and the
    /// distance. Slots let callers keep primitive data in leaf order, one
    /// indirection and cache miss fewer per test.
    pub fn closest_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        mut test: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        let mut best: Option<(u32, f32)> = None;
        let mut t_max = t_max;
        self.walk(ray, &mut t_max, |prim, t_max| {
            if let Some(t) = test(prim, *t_max) {
                *t_max = t;
                best = Some((prim, t));
            }
            false
        });
        best
    }

    /// Whether anything is hit in `(0, t_max)` (`test` as for
    /// [`Bvh::closest_hit`]).
    pub fn any_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        mut test: impl FnMut(u32, f32) -> Option<f32>,
    ) -> bool {
        let mut t = t_max;
        let mut hit = false;
        self.walk(ray, &mut t, |prim, t_max| {
            hit = test(prim, *t_max).is_some();
            hit
        });
        hit
    }

    /// Visits the slots of every leaf the ray enters before `t_max`, nearer
    /// child first; `visit` may lower `t_max` and returns true to stop.
    fn walk(&self, ray: &Ray, t_max: &mut f32, mut visit: impl FnMut(u32, &mut f32) -> bool) {
        if self.nodes.is_empty() {
            return;
        }
        let tr = Traversal::new(ray);
        let root = &self.nodes[0];
        if tr.enter(root.min, root.max, *t_max).is_none() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut top = 0usize;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.is_leaf() {
                for slot in n.index..n.index + n.count {
                    if visit(slot, t_max) {
                        return;
                    }
                }
            } else {
                let (l, r) = (n.index as usize, n.index as usize + 1);
                let (nl, nr) = (&self.nodes[l], &self.nodes[r]);
                let tl = tr.enter(nl.min, nl.max, *t_max);
                let trr = tr.enter(nr.min, nr.max, *t_max);
                match (tl, trr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b { (l, r) } else { (r, l) };
                        stack[top] = far as u32;
                        top += 1;
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            node = stack[top] as usize;
        }
    }
}

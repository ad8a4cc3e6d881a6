//! Stack traversal of the flat node array, nearer child first: closest hit
//! (shrinking `t_max` as hits are found) and any hit (stop at the first).
//! The primitive test is a closure, so meshes, analytic shapes and tests
//! against brute force share one traversal; the WGSL mirror reads the same
//! nodes.

use super::node::Bvh;
use super::node::BvhNode;
use fogbank_math::Ray;
use glam::Vec3A;

const STACK: usize = 64;

/// A ray prepared for box tests: origin and reciprocal direction in SIMD
/// lanes (x, y, z; the fourth is ignored), and the rounding allowance that
/// keeps a box containing a hit from being missed.
pub(crate) struct Traversal {
    o: Vec3A,
    inv_d: Vec3A,
}

/// 1 + 2γ₃ (pbrt-v4 §6.8.2): the far slab distance grows by this factor.
pub(crate) const SLAB_GROW: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// `t_max` with the rounding allowance: a box whose entry rounds just past
/// a hit already found (a neighbouring triangle across a shared edge gives
/// the same point a t one ulp apart) is still entered. Finite.
#[inline(always)]
pub(crate) fn grown(t_max: f32) -> f32 {
    (t_max * SLAB_GROW).min(f32::MAX)
}

impl Traversal {
    pub(crate) fn new(ray: &Ray) -> Traversal {
        Traversal {
            o: Vec3A::from(ray.o),
            inv_d: Vec3A::ONE / Vec3A::from(ray.d),
        }
    }

    /// Entry distance of the ray into the box within `(0, t_max)`, or None.
    /// The three slabs are tested side by side in SIMD lanes. An axis the
    /// ray runs parallel to (1/d = ±∞) makes `0 · ∞ = NaN` when the origin
    /// lies on one of the box's planes on that axis: the origin is then in
    /// the closed slab, so that axis constrains nothing. (SIMD min/max do
    /// not skip NaN as `f32::min` does, hence the explicit mask.) `t_max`
    /// is finite: an infinite one would let a box the parallel ray misses
    /// (entry at +∞) through.
    #[inline(always)]
    fn enter(&self, node: &BvhNode, t_max: f32) -> Option<f32> {
        self.enter_box(
            Vec3A::from_array(node.min),
            Vec3A::from_array(node.max),
            t_max,
        )
    }

    /// [`Self::enter`] for the box `min ..= max`.
    #[inline(always)]
    pub(crate) fn enter_box(&self, min: Vec3A, max: Vec3A, t_max: f32) -> Option<f32> {
        let ta = (min - self.o) * self.inv_d;
        let tb = (max - self.o) * self.inv_d;
        let free = ta.is_nan_mask() | tb.is_nan_mask();
        let near = Vec3A::select(free, Vec3A::ZERO, ta.min(tb));
        let far = Vec3A::select(free, Vec3A::splat(t_max), ta.max(tb) * SLAB_GROW);
        let t0 = near.max_element().max(0.0);
        let t1 = far.min_element().min(grown(t_max));
        (t0 <= t1).then_some(t0)
    }
}

/// A hierarchy that visits the leaf slots a ray may hit, and the
/// closest-hit and any-hit queries written once over that walk (for the
/// GPU's binary [`Bvh`] and the CPU's [`crate::WideBvh`] alike).
pub trait Walk {
    /// Visits the slots of every leaf the ray enters before `t_max`;
    /// `visit` may lower `t_max` and returns true to stop.
    fn walk(&self, ray: &Ray, t_max: &mut f32, visit: impl FnMut(u32, &mut f32) -> bool);

    /// The closest hit in `(0, t_max)`: `test(slot, t_max)` returns the hit
    /// distance of the primitive in leaf slot `slot` if it is below
    /// `t_max`. Returns the slot and the distance. Slots let callers keep
    /// primitive data in leaf order, one indirection and cache miss fewer
    /// per test.
    fn closest_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        mut test: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        let mut best: Option<(u32, f32)> = None;
        let mut t_max = t_max;
        self.walk(ray, &mut t_max, |slot, t_max| {
            if let Some(t) = test(slot, *t_max) {
                *t_max = t;
                best = Some((slot, t));
            }
            false
        });
        best
    }

    /// Whether anything is hit in `(0, t_max)` (`test` as for
    /// [`Walk::closest_hit`]).
    fn any_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        mut test: impl FnMut(u32, f32) -> Option<f32>,
    ) -> bool {
        let mut t = t_max;
        let mut hit = false;
        self.walk(ray, &mut t, |slot, t_max| {
            hit = test(slot, *t_max).is_some();
            hit
        });
        hit
    }
}

impl Walk for Bvh {
    /// Nearer child first; far children wait with their entry distance.
    fn walk(&self, ray: &Ray, t_max: &mut f32, mut visit: impl FnMut(u32, &mut f32) -> bool) {
        if self.nodes.is_empty() {
            return;
        }
        // Finite from here on (see Traversal::enter); hits only lower it.
        *t_max = t_max.min(f32::MAX);
        let tr = Traversal::new(ray);
        let root = &self.nodes[0];
        if tr.enter(root, *t_max).is_none() {
            return;
        }
        // Far children wait with their entry distance: one whose entry lies
        // beyond a hit found meanwhile is dropped unvisited.
        let mut stack = [(0u32, 0.0f32); STACK];
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
                let tl = tr.enter(&self.nodes[l], *t_max);
                let trr = tr.enter(&self.nodes[r], *t_max);
                match (tl, trr) {
                    (Some(a), Some(b)) => {
                        let (near, far, t_enter) = if a <= b { (l, r, b) } else { (r, l, a) };
                        stack[top] = (far as u32, t_enter);
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
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let (next, t_enter) = stack[top];
                if t_enter <= grown(*t_max) {
                    node = next as usize;
                    break;
                }
            }
        }
    }
}

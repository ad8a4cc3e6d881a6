//! A bounding-volume hierarchy over the media's world boxes, so a ray in a
//! scene of many media (Hansen 2025's 250 instanced clouds, Fig. 4.10) visits
//! only the media whose boxes it crosses, nearest first, instead of all.
//! Built by median splits of the box centres along the widest axis.

use fogbank_math::{Aabb, Ray, Vec3};

/// Media per leaf.
const LEAF: usize = 2;

#[derive(Clone, Debug)]
struct Node {
    bounds: Aabb,
    /// Leaf: `order[first..first + count]`; inner node: children at
    /// `first` and `first + 1` (`count` = 0).
    first: u32,
    count: u32,
}

#[derive(Clone, Debug)]
pub struct MediaBvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

fn union(boxes: &[Aabb], ids: &[u32]) -> Aabb {
    let mut b = Aabb::new(Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &i in ids {
        b.min = b.min.min(boxes[i as usize].min);
        b.max = b.max.max(boxes[i as usize].max);
    }
    b
}

impl MediaBvh {
    pub fn build(boxes: &[Aabb]) -> MediaBvh {
        let mut bvh = MediaBvh {
            nodes: Vec::with_capacity(2 * boxes.len().max(1)),
            order: (0..boxes.len() as u32).collect(),
        };
        bvh.nodes.push(Node {
            bounds: union(boxes, &bvh.order),
            first: 0,
            count: boxes.len() as u32,
        });
        // Split nodes breadth-first until leaves are small.
        let mut at = 0;
        while at < bvh.nodes.len() {
            let (first, count) = (bvh.nodes[at].first as usize, bvh.nodes[at].count as usize);
            if count > LEAF {
                let ids = &mut bvh.order[first..first + count];
                let centre = |i: &u32| {
                    let b = &boxes[*i as usize];
                    0.5 * (b.min + b.max)
                };
                let (lo, hi) = ids.iter().fold(
                    (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                    |(lo, hi), i| (lo.min(centre(i)), hi.max(centre(i))),
                );
                let axis = (hi - lo).max_position();
                let mid = count / 2;
                ids.select_nth_unstable_by(mid, |a, b| centre(a)[axis].total_cmp(&centre(b)[axis]));
                let child = bvh.nodes.len() as u32;
                for (s, c) in [(first, mid), (first + mid, count - mid)] {
                    let bounds = union(boxes, &bvh.order[s..s + c]);
                    bvh.nodes.push(Node {
                        bounds,
                        first: s as u32,
                        count: c as u32,
                    });
                }
                bvh.nodes[at].first = child;
                bvh.nodes[at].count = 0;
            }
            at += 1;
        }
        bvh
    }

    /// Number of media indexed.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// Calls `visit(medium)` for every medium whose box `ray` crosses in
    /// `[0, t_max()]`, nearer subtrees first; `t_max` is read again before
    /// each node, so a caller that shortens the ray (a collision found)
    /// prunes what lies beyond.
    pub fn visit(&self, ray: &Ray, mut t_max: impl FnMut() -> f32, mut visit: impl FnMut(usize)) {
        if self.order.is_empty() {
            return;
        }
        // Depth is at most log2(media) + 1 ≤ 64 for any count that fits.
        let mut stack = [(0u32, 0f32); 64];
        let mut top = 0;
        let slabs = Slabs::new(ray);
        if let Some(t0) = slabs.entry(&self.nodes[0].bounds, t_max()) {
            stack[0] = (0, t0);
            top = 1;
        }
        while top > 0 {
            top -= 1;
            let (n, entry) = stack[top];
            if entry > t_max() {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.count > 0 {
                for &i in &self.order[node.first as usize..(node.first + node.count) as usize] {
                    visit(i as usize);
                }
                continue;
            }
            let limit = t_max();
            let hit = |c: u32| {
                slabs
                    .entry(&self.nodes[c as usize].bounds, limit)
                    .map(|t0| (c, t0))
            };
            // Push the farther child first so the nearer one pops next.
            match (hit(node.first), hit(node.first + 1)) {
                (Some(a), Some(b)) => {
                    let (near, far) = if a.1 <= b.1 { (a, b) } else { (b, a) };
                    stack[top] = far;
                    stack[top + 1] = near;
                    top += 2;
                }
                (Some(a), None) | (None, Some(a)) => {
                    stack[top] = a;
                    top += 1;
                }
                (None, None) => {}
            }
        }
    }
}

/// Slab tests of one ray against many boxes, its reciprocal direction
/// computed once; a zero direction component is tested by position (no
/// 0 · ∞ = NaN), like [`Aabb::intersect`].
struct Slabs {
    o: [f32; 3],
    inv: [f32; 3],
    flat: [bool; 3],
}

impl Slabs {
    fn new(ray: &Ray) -> Slabs {
        let d = ray.d.to_array();
        Slabs {
            o: ray.o.to_array(),
            inv: d.map(|x| 1.0 / x),
            flat: d.map(|x| x == 0.0),
        }
    }

    /// Where the ray enters `b` within `[0, t_max]`, if it does.
    #[inline]
    fn entry(&self, b: &Aabb, t_max: f32) -> Option<f32> {
        let (mut t0, mut t1) = (0.0f32, t_max);
        for a in 0..3 {
            let (lo, hi) = (b.min[a], b.max[a]);
            if self.flat[a] {
                if self.o[a] < lo || self.o[a] > hi {
                    return None;
                }
                continue;
            }
            let ta = (lo - self.o[a]) * self.inv[a];
            let tb = (hi - self.o[a]) * self.inv[a];
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        (t0 <= t1).then_some(t0)
    }
}

#[cfg(test)]
mod media_bvh_test {
    use super::*;
    use fogbank_math::Pcg32;

    /// Every box a ray crosses is visited exactly once; boxes it misses
    /// are visited at most once (a leaf's other box) and far fewer than all.
    #[test]
    fn visits_exactly_the_crossed_boxes() {
        let mut rng = Pcg32::new(1, 2);
        let mut r = || rng.next_f32();
        let boxes: Vec<Aabb> = (0..300)
            .map(|_| {
                let c = Vec3::new(r(), r(), r()) * 10.0;
                let h = Vec3::new(r(), r(), r()) * 0.8 + Vec3::splat(0.05);
                Aabb::new(c - h, c + h)
            })
            .collect();
        let bvh = MediaBvh::build(&boxes);
        for k in 0..500 {
            let o = Vec3::new(r(), r(), r()) * 14.0 - Vec3::splat(2.0);
            let mut d = (Vec3::new(r(), r(), r()) - Vec3::splat(0.5)).normalize();
            if k % 5 == 0 {
                d[k % 3] = 0.0; // axis-parallel components
            }
            let ray = Ray::new(o, d);
            let t_max = if k % 2 == 0 { f32::INFINITY } else { 4.0 };
            let mut seen = vec![0u32; boxes.len()];
            bvh.visit(&ray, || t_max, |i| seen[i] += 1);
            let mut extra = 0;
            for (i, b) in boxes.iter().enumerate() {
                let hit = b.intersect(&ray, 0.0, t_max).is_some();
                assert!(
                    seen[i] == hit as u32 || (!hit && seen[i] == 1),
                    "ray {k}, box {i}"
                );
                extra += (!hit && seen[i] == 1) as u32;
            }
            assert!(extra < 60, "ray {k}: {extra} boxes visited in vain");
        }
    }
}

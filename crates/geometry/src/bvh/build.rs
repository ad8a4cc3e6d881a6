//! Binned SAH construction (Wald 2007): at each node the primitives'
//! centroids are binned along each axis, the split between bins with the
//! lowest surface-area cost wins, and a node becomes a leaf when no split
//! beats intersecting its primitives directly. Deterministic: the same
//! boxes give the same nodes.

use super::node::{Bvh, BvhNode};
use fogbank_math::{Aabb, Vec3};

const BINS: usize = 16;
/// Leaves never hold more (a split is forced, by median if need be).
const MAX_LEAF: usize = 8;
/// Cost of visiting a node relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;
/// Beyond this depth splits are by median, which halves the count: the
/// depth stays below the traversal stack's 64 entries whatever the input.
const MEDIAN_DEPTH: usize = 32;

fn empty() -> Aabb {
    Aabb::new(Vec3::INFINITY, Vec3::NEG_INFINITY)
}

fn grow(b: &mut Aabb, o: &Aabb) {
    b.min = b.min.min(o.min);
    b.max = b.max.max(o.max);
}

fn area(b: &Aabb) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    let e = b.max - b.min;
    2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
}

pub(super) fn build(bounds: &[Aabb]) -> Bvh {
    let mut order: Vec<u32> = (0..bounds.len() as u32)
        .filter(|&i| !bounds[i as usize].is_empty())
        .collect();
    if order.is_empty() {
        return Bvh::default();
    }
    let centroid: Vec<Vec3> = bounds.iter().map(|b| 0.5 * (b.min + b.max)).collect();
    let mut nodes = vec![BvhNode::default()];
    // (node, first, end, depth)
    let mut stack = vec![(0usize, 0usize, order.len(), 1usize)];
    while let Some((node, first, end, depth)) = stack.pop() {
        let prims = &mut order[first..end];
        let mut b = empty();
        let mut cb = empty();
        for &p in prims.iter() {
            grow(&mut b, &bounds[p as usize]);
            let c = centroid[p as usize];
            grow(&mut cb, &Aabb::new(c, c));
        }
        let n = prims.len();
        let split = if n <= 1 {
            None
        } else if depth >= MEDIAN_DEPTH {
            Some(median(prims, &centroid, &cb))
        } else {
            sah_split(prims, bounds, &centroid, &b, &cb)
                .or_else(|| (n > MAX_LEAF).then(|| median(prims, &centroid, &cb)))
        };
        let out = &mut nodes[node];
        out.min = b.min.to_array();
        out.max = b.max.to_array();
        match split {
            None => {
                out.count = n as u32;
                out.index = first as u32;
            }
            Some(mid) => {
                let left = nodes.len();
                nodes[node].count = 0;
                nodes[node].index = left as u32;
                nodes.push(BvhNode::default());
                nodes.push(BvhNode::default());
                // Right first on the stack so the left subtree is laid out
                // first (better locality for the near-first traversal).
                stack.push((left + 1, first + mid, end, depth + 1));
                stack.push((left, first, first + mid, depth + 1));
            }
        }
    }
    Bvh { nodes, order }
}

/// Splits at the median centroid along the longest centroid axis; returns
/// the count on the left (≥ 1).
fn median(prims: &mut [u32], centroid: &[Vec3], cb: &Aabb) -> usize {
    let axis = (cb.max - cb.min).max_position();
    let mid = prims.len() / 2;
    prims.select_nth_unstable_by(mid, |&a, &b| {
        centroid[a as usize][axis]
            .total_cmp(&centroid[b as usize][axis])
            .then(a.cmp(&b))
    });
    mid
}

/// The best binned-SAH split, partitioning `prims` in place, or `None`
/// when a leaf is cheaper (and allowed) or the centroids coincide.
fn sah_split(
    prims: &mut [u32],
    bounds: &[Aabb],
    centroid: &[Vec3],
    b: &Aabb,
    cb: &Aabb,
) -> Option<usize> {
    let n = prims.len();
    let extent = cb.max - cb.min;
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, bin)
    for axis in 0..3 {
        // Zero (all centroids in one plane) or NaN: nothing to split.
        if extent[axis].partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        let scale = BINS as f32 / extent[axis];
        let bin_of =
            |p: u32| (((centroid[p as usize][axis] - cb.min[axis]) * scale) as usize).min(BINS - 1);
        let mut boxes = [empty(); BINS];
        let mut counts = [0usize; BINS];
        for &p in prims.iter() {
            let k = bin_of(p);
            counts[k] += 1;
            grow(&mut boxes[k], &bounds[p as usize]);
        }
        // Sweep from the right for suffix areas, then from the left.
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc, mut cnt) = (empty(), 0);
        for k in (1..BINS).rev() {
            grow(&mut acc, &boxes[k]);
            cnt += counts[k];
            right_area[k] = area(&acc);
            right_count[k] = cnt;
        }
        let (mut acc, mut cnt) = (empty(), 0);
        for k in 0..BINS - 1 {
            grow(&mut acc, &boxes[k]);
            cnt += counts[k];
            if cnt == 0 || right_count[k + 1] == 0 {
                continue;
            }
            let cost = area(&acc) * cnt as f32 + right_area[k + 1] * right_count[k + 1] as f32;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k));
            }
        }
    }
    let (cost, axis, k) = best?;
    let parent = area(b).max(f32::MIN_POSITIVE);
    let split_cost = TRAVERSAL_COST + cost / parent;
    if split_cost >= n as f32 && n <= MAX_LEAF {
        return None;
    }
    let scale = BINS as f32 / extent[axis];
    let left = |p: &u32| {
        (((centroid[*p as usize][axis] - cb.min[axis]) * scale) as usize).min(BINS - 1) <= k
    };
    // Stable partition (left side first, order kept): deterministic, and
    // linear where sorting on the side was n log n.
    let (l, r): (Vec<u32>, Vec<u32>) = prims.iter().partition(|p| left(p));
    let mid = l.len();
    prims[..mid].copy_from_slice(&l);
    prims[mid..].copy_from_slice(&r);
    (mid > 0 && mid < n).then_some(mid)
}

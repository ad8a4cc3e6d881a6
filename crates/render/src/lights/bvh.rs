//! The light BVH over a scene's emitting triangles (Conty Estevez & Kulla
//! 2018, pbrt-v4's `BVHLightSampler`): from a receiving point, a light is
//! picked by descending the tree, choosing each child in proportion to its
//! [`LightBounds::importance`], so lights near a point and facing it are
//! picked often and lights behind it never. The probability of a given
//! light is re-derived by the same descent along its bit trail (MIS
//! needs it for emission that a phase or BSDF direction hits). With
//! thousands of small emitters this replaces picking by power alone,
//! which spends most samples on lights far away.

use super::light_bounds::{Importance, LightBounds};
use fogbank_math::Vec3;

/// One node, depth first: an interior node's first child follows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightNode {
    pub bounds: LightBounds,
    /// What the descent evaluates of `bounds`.
    pub importance: Importance,
    /// Leaf: the light's index in the scene's lights; interior: the index
    /// of the second child.
    pub index: u32,
    pub leaf: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct LightBvh {
    pub nodes: Vec<LightNode>,
    /// Lights `first .. first + trails.len()` are the ones this tree may
    /// hold.
    pub first: usize,
    /// Per light from `first` on: bit k set when the path from the root
    /// takes the second child at depth k; [`NOT_IN_TREE`] for lights
    /// without power.
    pub trails: Vec<u32>,
}

/// The trail of a light the tree does not hold.
pub const NOT_IN_TREE: u32 = u32::MAX;
/// Trails are 32 bits: the builder keeps every leaf shallower than this.
const MAX_DEPTH: u32 = 31;
const BUCKETS: usize = 12;

impl LightBvh {
    /// The tree over `items` (light index, bounds; light indices in
    /// `first .. first + count`); `None` when no item has power.
    pub fn build(first: usize, count: usize, items: &[(u32, LightBounds)]) -> Option<LightBvh> {
        let mut items: Vec<(u32, LightBounds)> = (items.iter())
            .filter(|(_, b)| b.phi > 0.0 && b.phi.is_finite())
            .copied()
            .collect();
        if items.is_empty() {
            return None;
        }
        let mut bvh = LightBvh {
            nodes: Vec::with_capacity(2 * items.len()),
            first,
            trails: vec![NOT_IN_TREE; count],
        };
        bvh.build_node(&mut items, 0, 0);
        Some(bvh)
    }

    fn build_node(&mut self, items: &mut [(u32, LightBounds)], depth: u32, trail: u32) -> usize {
        let at = self.nodes.len();
        if let [(light, bounds)] = items {
            self.trails[*light as usize - self.first] = trail;
            self.nodes.push(LightNode {
                bounds: *bounds,
                importance: (&*bounds).into(),
                index: *light,
                leaf: true,
            });
            return at;
        }
        let bounds = (items[1..].iter()).fold(items[0].1, |b, (_, o)| b.union(o));
        self.nodes.push(LightNode {
            bounds,
            importance: (&bounds).into(),
            index: 0,
            leaf: false,
        });
        let mid = split(items, &bounds, depth);
        let (left, right) = items.split_at_mut(mid);
        self.build_node(left, depth + 1, trail);
        let second = self.build_node(right, depth + 1, trail | 1 << depth);
        self.nodes[at].index = second as u32;
        at
    }

    /// Whether light `i` is one of the tree's (picked through it).
    pub fn holds(&self, i: usize) -> bool {
        i >= self.first && i < self.first + self.trails.len()
    }

    /// Probability of the first child of interior node `n` at `p` (`None`
    /// when neither child can light `p`).
    fn first_child_probability(&self, n: usize, p: Vec3) -> Option<f32> {
        let second = self.nodes[n].index as usize;
        let i0 = self.nodes[n + 1].importance.of(p);
        let i1 = self.nodes[second].importance.of(p);
        let sum = i0 + i1;
        (sum > 0.0).then(|| i0 / sum)
    }

    /// (light index, probability) of a light picked for point `p` with
    /// `u` ∈ [0, 1).
    pub fn pick(&self, mut u: f32, p: Vec3) -> Option<(usize, f32)> {
        let (mut n, mut pmf) = (0, 1.0f32);
        loop {
            let node = &self.nodes[n];
            if node.leaf {
                return Some((node.index as usize, pmf));
            }
            let p0 = self.first_child_probability(n, p)?;
            if u < p0 {
                u = (u / p0).min(ONE_MINUS_EPSILON);
                pmf *= p0;
                n += 1;
            } else {
                u = ((u - p0) / (1.0 - p0)).min(ONE_MINUS_EPSILON);
                pmf *= 1.0 - p0;
                n = node.index as usize;
            }
        }
    }

    /// The probability that [`LightBvh::pick`] at `p` returns light `i`.
    pub fn pmf(&self, i: usize, p: Vec3) -> f32 {
        let Some(&trail) = i.checked_sub(self.first).and_then(|k| self.trails.get(k)) else {
            return 0.0;
        };
        if trail == NOT_IN_TREE {
            return 0.0;
        }
        let (mut n, mut pmf, mut depth) = (0, 1.0f32, 0);
        while !self.nodes[n].leaf {
            let Some(p0) = self.first_child_probability(n, p) else {
                return 0.0;
            };
            if trail >> depth & 1 == 0 {
                pmf *= p0;
                n += 1;
            } else {
                pmf *= 1.0 - p0;
                n = self.nodes[n].index as usize;
            }
            depth += 1;
        }
        pmf
    }
}

const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Partitions `items` (≥ 2) and returns the first index of the second
/// part: the bucket boundary of least cost φ·M_Ω·area (pbrt-v4's, with its
/// regulariser for thin boxes) along any axis, or a median split when the
/// centroids coincide, no bucket boundary separates them or the depth
/// budget of the trails is nearly spent.
fn split(items: &mut [(u32, LightBounds)], bounds: &LightBounds, depth: u32) -> usize {
    let n = items.len();
    let (lo, hi) = (items.iter()).fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (_, b)| {
        (lo.min(b.centroid()), hi.max(b.centroid()))
    });
    let extent = hi - lo;
    let axis = extent.max_position();
    let median = |items: &mut [(u32, LightBounds)]| {
        let key = |b: &LightBounds| b.centroid()[axis];
        items.select_nth_unstable_by(n / 2, |a, b| key(&a.1).total_cmp(&key(&b.1)));
        n / 2
    };
    let levels_left = usize::BITS - (n - 1).leading_zeros();
    if extent[axis] <= 0.0 || depth + levels_left >= MAX_DEPTH {
        return median(items);
    }
    // The bucket of a light's centroid along axis `a`.
    let bucket = |b: &LightBounds, a: usize| {
        let f = (b.centroid()[a] - lo[a]) / extent[a];
        ((f * BUCKETS as f32) as usize).min(BUCKETS - 1)
    };
    let size = bounds.max - bounds.min;
    let mut best: Option<(f32, usize, usize)> = None;
    for a in 0..3 {
        if extent[a] <= 0.0 {
            continue;
        }
        let mut buckets: [Option<LightBounds>; BUCKETS] = [None; BUCKETS];
        for (_, b) in items.iter() {
            let k = bucket(b, a);
            buckets[k] = Some(buckets[k].map_or(*b, |s| s.union(b)));
        }
        let regulariser = size.max_element() / size[a].max(f32::MIN_POSITIVE);
        let cost = |b: Option<LightBounds>| {
            b.map_or(0.0, |b| {
                let d = b.max - b.min;
                b.phi * b.measure() * 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
            })
        };
        let merge = |acc: Option<LightBounds>, b: &Option<LightBounds>| match (acc, b) {
            (Some(x), Some(y)) => Some(x.union(y)),
            (x, y) => x.or(*y),
        };
        for k in 1..BUCKETS {
            let left = buckets[..k].iter().fold(None, merge);
            let right = buckets[k..].iter().fold(None, merge);
            if left.is_none() || right.is_none() {
                continue;
            }
            let c = regulariser * (cost(left) + cost(right));
            if best.is_none_or(|(b, _, _)| c < b) {
                best = Some((c, a, k));
            }
        }
    }
    let Some((_, a, k_cut)) = best else {
        return median(items);
    };
    // Partition by the bucket test the costs used.
    let mut mid = 0;
    for i in 0..n {
        if bucket(&items[i].1, a) < k_cut {
            items.swap(i, mid);
            mid += 1;
        }
    }
    if mid == 0 || mid == n {
        return median(items);
    }
    mid
}

#[cfg(test)]
mod bvh_test {
    use super::*;
    use fogbank_math::Pcg32;

    /// `count` small triangles with random position and facing.
    pub(crate) fn scatter(count: usize, rng: &mut Pcg32) -> Vec<(u32, LightBounds)> {
        (0..count)
            .map(|i| {
                let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 - 2.0;
                let n = crate::lights::light_bounds::light_bounds_test::unit(rng);
                let (t, b) = (
                    n.any_orthonormal_pair().0 * 0.05,
                    n.any_orthonormal_pair().1 * 0.05,
                );
                let phi = if i % 7 == 3 {
                    0.0
                } else {
                    0.5 + rng.next_f32()
                };
                (
                    10 + i as u32,
                    LightBounds::triangle([o, o + t, o + b], n, phi),
                )
            })
            .collect()
    }

    #[test]
    fn picks_follow_the_pmf() {
        let mut rng = Pcg32::new(7, 8);
        let items = scatter(300, &mut rng);
        let bvh = LightBvh::build(10, 300, &items).unwrap();
        assert_eq!(
            bvh.nodes.len(),
            2 * 257 - 1,
            "lights without power are left out"
        );
        for trial in 0..6 {
            let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 5.0 - 2.5;
            let pmfs: Vec<f64> = (0..320).map(|i| bvh.pmf(i, p) as f64).collect();
            let total: f64 = pmfs.iter().sum();
            for (i, b) in &items {
                if b.phi == 0.0 {
                    assert_eq!(pmfs[*i as usize], 0.0);
                }
            }
            // Chi-square of picks against the pmf (bins with expected
            // counts ≥ 5, the rest pooled).
            let draws = 200_000;
            let mut counts = vec![0u32; 320];
            let mut failed = 0;
            for _ in 0..draws {
                let Some((i, pmf)) = bvh.pick(rng.next_f32(), p) else {
                    failed += 1;
                    continue;
                };
                assert_eq!(pmf, bvh.pmf(i, p), "pick and pmf disagree for light {i}");
                counts[i] += 1;
            }
            // Picks fail where a node some light's bound reaches has no
            // child that reaches (pbrt-v4's sampler does the same): that
            // mass is 1 − Σ pmf, a bin of its own. Random normals are the
            // worst case; here 8–18 %.
            assert!(total > 0.8, "Σ pmf = {total}");
            let bins = pmfs.iter().copied().chain([1.0 - total]);
            counts.push(failed);
            let (mut chi2, mut dof, mut pooled_e, mut pooled_o) = (0.0, 0, 0.0, 0.0);
            for (i, pm) in bins.enumerate() {
                let e = pm * draws as f64;
                if e >= 5.0 {
                    chi2 += (counts[i] as f64 - e).powi(2) / e;
                    dof += 1;
                } else {
                    pooled_e += e;
                    pooled_o += counts[i] as f64;
                }
            }
            if pooled_e > 0.0 {
                chi2 += (pooled_o - pooled_e).powi(2) / pooled_e.max(1e-9);
                dof += 1;
            }
            let p_value = fogbank_math::chi2::gamma_q((dof - 1) as f64 / 2.0, chi2 / 2.0);
            assert!(
                p_value > 1e-4,
                "trial {trial}: χ² = {chi2} over {dof} bins, p = {p_value}"
            );
        }
    }

    #[test]
    fn deep_trees_keep_their_trails_in_32_bits() {
        // Geometrically shrinking clusters make the SAH split off one light
        // at a time; the depth budget must turn to median splits.
        let items: Vec<(u32, LightBounds)> = (0..5000)
            .map(|i| {
                let x = 0.5f32.powi(i.min(120)) + i as f32 * 1e-7;
                let o = Vec3::new(x, 0.0, 0.0);
                let t = [o, o + Vec3::Y * 1e-3, o + Vec3::Z * 1e-3];
                (i as u32, LightBounds::triangle(t, Vec3::X, 1.0))
            })
            .collect();
        let bvh = LightBvh::build(0, items.len(), &items).unwrap();
        let p = Vec3::new(3.0, 0.1, 0.0);
        let total: f32 = (0..items.len()).map(|i| bvh.pmf(i, p)).sum();
        assert!((total - 1.0).abs() < 1e-3, "{total}");
        assert!(bvh.trails.iter().all(|&t| t != NOT_IN_TREE));
    }
}

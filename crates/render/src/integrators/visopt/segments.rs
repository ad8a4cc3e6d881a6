//! The per-ray importance segments of Lerzer and Dachsbacher 2025 §5.1: a sorted list of
//! entries (t_i, l_i, k_i, K_i) approximating the step function k(t) of the
//! importance along one ray, with K_i = ∫₀^{t_i} k̃² the prefix integral
//! that makes h(y) (Eq. 7) two lookups.
//!
//! t runs from the volume entry x (t = 0) to the exit z (t = `length`).
//! An entry is a point (l = 0) or a segment [t, t + l] of constant k.
//! Between entries lie unsampled gaps, whose importance is the mean of the
//! two neighbours' (0 beyond the ray's ends, §5.1); their integrand is the
//! square of that mean (the paper leaves open which mean; checklist §1).
//!
//! The merge is Alg. 1 with its slip corrected (checklist erratum 3): a
//! candidate inside the current entry is tested for containment *before*
//! merging, so a same-k point inside a segment is discarded instead of
//! shrinking it; a split re-queues the old right end in t order.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// One entry of the list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Start t_i (distance from the volume entry, in the caller's units).
    pub t: f32,
    /// Length l_i ≥ 0 (0: a point sample).
    pub l: f32,
    /// Importance k_i ∈ [0, 1].
    pub k: f32,
    /// K_i = ∫₀^{t_i} k̃(s)² ds.
    pub big_k: f32,
}

impl Segment {
    pub fn point(t: f32, k: f32) -> Segment {
        Segment {
            t,
            l: 0.0,
            k,
            big_k: 0.0,
        }
    }

    #[inline]
    pub fn right(&self) -> f32 {
        self.t + self.l
    }
}

/// A candidate in the merge queue, ordered by t (then by right end, so a
/// point sorts before a segment starting at the same t).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Queued(Segment);

impl Eq for Queued {}
impl Ord for Queued {
    fn cmp(&self, o: &Self) -> Ordering {
        // Reversed: BinaryHeap is a max-heap and we pop the smallest t.
        (o.0.t, o.0.right())
            .partial_cmp(&(self.0.t, self.0.right()))
            .unwrap_or(Ordering::Equal)
    }
}
impl PartialOrd for Queued {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Alg. 1 (corrected) for one candidate against the last entry of `list`;
/// returns the entry to re-queue after a split.
fn insert(list: &mut Vec<Segment>, cand: Segment, d: f32, tolerance: f32) -> Option<Segment> {
    let Some(curr) = list.last_mut() else {
        list.push(cand);
        return None;
    };
    let inside = cand.t >= curr.t && cand.right() <= curr.right();
    if (curr.k - cand.k).abs() <= tolerance {
        if inside {
            return None; // redundant: already covered (Alg. 1 l. 10–12)
        }
        if cand.t - curr.right() < d {
            // Close enough: extend curr (l. 6–9), never shrinking it.
            curr.l = curr.right().max(cand.right()) - curr.t;
            return None;
        }
    } else if cand.t >= curr.t && cand.t < curr.right() {
        // A different importance inside curr: split (l. 14–19). curr
        // keeps its left end as a point; its old right end comes back as
        // a point of its importance, in t order.
        let temp = Segment::point(curr.right(), curr.k);
        curr.l = 0.0;
        list.push(cand);
        return Some(temp);
    }
    list.push(cand);
    None
}

/// Merges the stored list `old` (sorted) with new point samples `samples`
/// (sorted by t) into `out` (cleared first) with merge distance `d`, and
/// computes every K_i for a ray of length `length`. Returns K(z) = ∫₀^L k̃².
pub fn merge(
    old: &[Segment],
    samples: &[(f32, f32)],
    d: f32,
    length: f32,
    out: &mut Vec<Segment>,
) -> f32 {
    merge_within(old, samples, d, 0.0, length, out)
}

/// [`merge`] for a continuous importance (pre-interpolative classification,
/// checklist §1): entries whose importance differs by at most `tolerance`
/// count as equal (the first one's value is kept).
pub fn merge_within(
    old: &[Segment],
    samples: &[(f32, f32)],
    d: f32,
    tolerance: f32,
    length: f32,
    out: &mut Vec<Segment>,
) -> f32 {
    out.clear();
    let mut requeued = BinaryHeap::new();
    let (mut i, mut j) = (0, 0);
    loop {
        // The smallest of the three queue heads.
        let a = old.get(i).copied();
        let b = samples.get(j).map(|&(t, k)| Segment::point(t, k));
        let c = requeued.peek().map(|q: &Queued| q.0);
        let key =
            |s: Option<Segment>| s.map_or((f32::INFINITY, f32::INFINITY), |s| (s.t, s.right()));
        let next = if key(a) <= key(b) && key(a) <= key(c) && a.is_some() {
            i += 1;
            a
        } else if key(b) <= key(c) && b.is_some() {
            j += 1;
            b
        } else if c.is_some() {
            requeued.pop();
            c
        } else {
            None
        };
        let Some(cand) = next else { break };
        if let Some(temp) = insert(out, cand, d, tolerance) {
            requeued.push(Queued(temp));
        }
    }
    integrate(out, length)
}

/// Fills K_i in one sweep (§5.1): segments add l_i k_i², gaps the square
/// of their neighbours' mean importance times their length (0 beyond the
/// ends). Returns K(z) for a ray of length `length`.
pub fn integrate(list: &mut [Segment], length: f32) -> f32 {
    let mut acc = 0.0f64;
    let (mut right, mut k_prev) = (0.0f32, 0.0f32);
    for s in list.iter_mut() {
        let mean = 0.5 * (k_prev + s.k) as f64;
        acc += (s.t - right).max(0.0) as f64 * mean * mean;
        s.big_k = acc as f32;
        acc += s.l as f64 * (s.k as f64).powi(2);
        right = right.max(s.right());
        k_prev = s.k;
    }
    let mean = 0.5 * k_prev as f64;
    acc += (length - right).max(0.0) as f64 * mean * mean;
    acc as f32
}

/// K(t) = ∫₀^t k̃² (§5.1): binary search for the last entry with t_i ≤ t;
/// inside it K_i + (t − t_i) k_i² (erratum 2: k_i squared); in the gap
/// after it, linear between its right end and the next entry's K (or
/// `big_k_z` at `length`).
pub fn integral_at(list: &[Segment], big_k_z: f32, length: f32, t: f32) -> f32 {
    let i = list.partition_point(|s| s.t <= t);
    let (k0, right) = if i == 0 {
        (0.0, 0.0)
    } else {
        let s = &list[i - 1];
        if t <= s.right() {
            return s.big_k + (t - s.t) * s.k * s.k;
        }
        (s.big_k + s.l * s.k * s.k, s.right())
    };
    let (k1, next_t) = match list.get(i) {
        Some(n) => (n.big_k, n.t),
        None => (big_k_z, length),
    };
    if next_t <= right {
        return k1.max(k0);
    }
    k0 + (k1 - k0) * ((t - right) / (next_t - right)).clamp(0.0, 1.0)
}

/// Lerzer and Dachsbacher 2025 Eq. 7, corrected (erratum 1): h(t) = r ∫ₓʸ k̃² + q ∫ᵧᶻ k̃²
/// = (r − q) K(t) + q K(z). Never negative for r, q ≥ 0.
#[inline]
pub fn h(list: &[Segment], big_k_z: f32, length: f32, t: f32, r: f32, q: f32) -> f32 {
    let k_t = integral_at(list, big_k_z, length, t).clamp(0.0, big_k_z);
    (r * k_t + q * (big_k_z - k_t)).max(0.0)
}

/// Lerzer and Dachsbacher 2025 Eq. 8: the optimisation factor μ'/μ = p / (p + (1 − g)^{2λ} h),
/// the same for absorption and scattering; in (0, 1] for p > 0.
#[inline]
pub fn mu_factor(p: f32, g: f32, lambda: f32, h: f32) -> f32 {
    let w = if lambda == 0.0 {
        1.0
    } else {
        (1.0 - g).max(0.0).powf(2.0 * lambda)
    };
    p / (p + w * h)
}

#[cfg(test)]
mod segments_test {
    use super::*;

    fn seg(t: f32, l: f32, k: f32) -> Segment {
        Segment {
            t,
            l,
            k,
            big_k: 0.0,
        }
    }

    /// (t, l, k) per entry, rounded to 1e-5 (sums like 2.1 + 2.4 round).
    fn shape(list: &[Segment]) -> Vec<(f32, f32, f32)> {
        let r = |x: f32| (x * 1e5).round() / 1e5;
        list.iter().map(|s| (r(s.t), r(s.l), s.k)).collect()
    }

    /// The shape of `old` merged with `new` (distance `d`, ray length 10).
    fn merged(old: &[Segment], new: &[(f32, f32)], d: f32) -> Vec<(f32, f32, f32)> {
        let mut out = Vec::new();
        merge(old, new, d, 10.0, &mut out);
        shape(&out)
    }

    #[test]
    fn same_importance_within_d_merges_into_a_segment_and_points_inside_are_discarded() {
        let mut out = Vec::new();
        merge(
            &[],
            &[(1.0, 1.0), (1.5, 1.0), (2.0, 1.0), (4.0, 1.0)],
            0.6,
            10.0,
            &mut out,
        );
        assert_eq!(shape(&out), vec![(1.0, 1.0, 1.0), (4.0, 0.0, 1.0)]);
        // A same-k point inside the segment is discarded and does not shrink
        // it (the printed order of Alg. 1 would set right = 1.2).
        let old = out.clone();
        merge(&old, &[(1.2, 1.0)], 0.6, 10.0, &mut out);
        assert_eq!(shape(&out), vec![(1.0, 1.0, 1.0), (4.0, 0.0, 1.0)]);
    }

    #[test]
    fn a_different_importance_splits_and_requeues_the_right_end() {
        // Segment [1, 3] of k = 1; a k = 0 sample at 2 splits it, the old
        // right end 3 comes back as a k = 1 point after a later sample 2.5.
        assert_eq!(
            merged(&[seg(1.0, 2.0, 1.0)], &[(2.0, 0.0), (2.5, 0.0)], 0.1),
            vec![
                (1.0, 0.0, 1.0),
                (2.0, 0.0, 0.0),
                (2.5, 0.0, 0.0),
                (3.0, 0.0, 1.0)
            ]
        );
        // Re-queued beyond the next new sample: it is still placed in order.
        assert_eq!(
            merged(&[seg(1.0, 2.0, 1.0)], &[(2.0, 0.0), (3.5, 1.0)], 0.1),
            vec![
                (1.0, 0.0, 1.0),
                (2.0, 0.0, 0.0),
                (3.0, 0.0, 1.0),
                (3.5, 0.0, 1.0)
            ]
        );
    }

    /// Fig. 4: two insertion steps on k = 0 | 1 on [2, 6) | 0.5 on [6, 8) | 0
    /// over a ray of length 10, with d = 1.5 (samples 1 apart merge).
    #[test]
    fn replays_the_two_insertion_steps_of_figure_4() {
        let k = |t: f32| {
            if (2.0..6.0).contains(&t) {
                1.0
            } else if (6.0..8.0).contains(&t) {
                0.5
            } else {
                0.0
            }
        };
        let mut first = Vec::new();
        let samples: Vec<(f32, f32)> = [0.5, 2.5, 4.5, 6.5, 8.5]
            .iter()
            .map(|&t| (t, k(t)))
            .collect();
        let kz = merge(&[], &samples, 2.5, 10.0, &mut first);
        assert_eq!(
            shape(&first),
            vec![
                (0.5, 0.0, 0.0),
                (2.5, 2.0, 1.0),
                (6.5, 0.0, 0.5),
                (8.5, 0.0, 0.0)
            ]
        );
        // K: gap [0, .5] of mean 0 → 0; gap [.5, 2.5] mean ½ → 2·¼ = .5;
        // segment 2·1; gap [4.5, 6.5] mean ¾ → 2·9/16; gap [6.5, 8.5]
        // mean ¼ → 2/16; end gap mean 0.
        let ks: Vec<f32> = first.iter().map(|s| s.big_k).collect();
        assert_eq!(ks, vec![0.0, 0.5, 2.5 + 1.125, 2.5 + 1.125 + 0.125]);
        assert_eq!(kz, 3.75);
        // Second step: samples at the change points refine the gaps, and one
        // inside the segment with the same k is discarded.
        let samples: Vec<(f32, f32)> = [1.9, 2.1, 3.0, 5.9, 6.1, 7.9, 8.1]
            .iter()
            .map(|&t| (t, k(t)))
            .collect();
        let mut second = Vec::new();
        let kz2 = merge(&first, &samples, 0.5, 10.0, &mut second);
        assert_eq!(
            shape(&second),
            vec![
                (0.5, 0.0, 0.0),
                (1.9, 0.0, 0.0),
                (2.1, 2.4, 1.0),
                (5.9, 0.0, 1.0),
                (6.1, 0.4, 0.5),
                (7.9, 0.0, 0.5),
                (8.1, 0.4, 0.0),
            ]
        );
        let exact = 4.0 * 1.0 + 2.0 * 0.25;
        assert!(
            (kz2 - exact).abs() < (kz - exact).abs() / 4.0,
            "{kz} → {kz2}, exact {exact}"
        );
        // K(t) is continuous and non-decreasing, and inside a segment adds
        // (t − t_i) k_i².
        let mut last = 0.0;
        for n in 0..=1000 {
            let t = n as f32 * 0.01;
            let v = integral_at(&second, kz2, 10.0, t);
            assert!(
                v >= last - 1e-6 && v - last < 0.02,
                "K({t}) = {v} after {last}"
            );
            last = v;
        }
        assert!((integral_at(&second, kz2, 10.0, 3.0) - (second[2].big_k + 0.9)).abs() < 1e-6);
        assert!((last - kz2).abs() < 1e-6);
    }

    #[test]
    fn h_is_never_negative_and_mu_factor_stays_in_unit_interval() {
        let mut list = Vec::new();
        let kz = merge(
            &[],
            &[(1.0, 1.0), (2.0, 1.0), (3.0, 0.0)],
            1.5,
            4.0,
            &mut list,
        );
        for n in 0..=40 {
            let t = n as f32 * 0.1;
            // r < q: the printed Eq. 7/14 would go negative near the exit.
            let v = h(&list, kz, 4.0, t, 30.0, 70.0);
            assert!(v >= 0.0);
            let f = mu_factor(1.0, 0.0, 1.0, v);
            assert!(f > 0.0 && f <= 1.0);
        }
        // p → ∞ or g = 1 or h = 0: no optimisation.
        assert_eq!(mu_factor(1.0, 1.0, 1.0, 5.0), 1.0);
        assert_eq!(mu_factor(1.0, 0.3, 1.0, 0.0), 1.0);
        assert_eq!(mu_factor(1.0, 0.5, 0.0, 1.0), 0.5);
    }
}

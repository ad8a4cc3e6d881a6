//! Where the importance along a camera ray is sampled (Lerzer and Dachsbacher 2025 §5.2):
//! a first pass of N equal strata, then adaptive passes that place strata
//! (a) in unsampled gaps between entries of different importance — where a
//! change point is bracketed — and (c) in the unsampled stretches at the
//! ray's ends, and (b) inside segments and same-importance gaps, where a
//! change may have been missed.
//!
//! The paper does not say how the strata are shared among (a)–(c); here a
//! fraction `gap_share` of them (default ½) goes to (a) + (c) and the rest
//! to (b), each proportional to length (stratified over the class's
//! intervals laid end to end), so change points are bracketed ever tighter
//! while thin features inside long segments are still searched.

use super::segments::Segment;
use fogbank_math::Pcg32;

/// Pass 1: one jittered sample in each of `n` equal strata of [0, length],
/// sorted.
pub fn uniform(length: f32, n: u32, rng: &mut Pcg32) -> Vec<f32> {
    strata(length, n, rng).collect()
}

/// [`uniform`] without collecting.
pub fn strata(length: f32, n: u32, rng: &mut Pcg32) -> impl Iterator<Item = f32> + '_ {
    (0..n).map(move |j| ((j as f32 + rng.next_f32()) / n as f32 * length).min(length))
}

/// An adaptive pass: `n` sorted sample positions for the list `list` of a
/// ray of length `length` (see the module docs).
pub fn adaptive(
    list: &[Segment],
    length: f32,
    n: u32,
    gap_share: f32,
    rng: &mut Pcg32,
) -> Vec<f32> {
    if list.is_empty() {
        return uniform(length, n, rng);
    }
    // (start, end, bracketing a change?)
    let mut intervals: Vec<(f32, f32, bool)> = Vec::with_capacity(2 * list.len() + 1);
    let first = list[0];
    intervals.push((0.0, first.t, true));
    let mut right = 0.0f32;
    for (i, s) in list.iter().enumerate() {
        if i > 0 {
            let prev = list[i - 1];
            intervals.push((right, s.t, prev.k != s.k));
        }
        intervals.push((s.t, s.right(), false));
        right = right.max(s.right());
    }
    intervals.push((right, length, true));
    intervals.retain(|&(a, b, _)| b > a);
    let total = |change: bool| -> f32 {
        intervals
            .iter()
            .filter(|i| i.2 == change)
            .map(|i| i.1 - i.0)
            .sum()
    };
    let (len_a, len_b) = (total(true), total(false));
    let n_a = match (len_a > 0.0, len_b > 0.0) {
        (false, _) => 0,
        (true, false) => n,
        (true, true) => ((gap_share.clamp(0.0, 1.0) * n as f32).round() as u32).min(n),
    };
    let mut out = Vec::with_capacity(n as usize);
    for (change, count, len) in [(true, n_a, len_a), (false, n - n_a, len_b)] {
        if count == 0 || len <= 0.0 {
            continue;
        }
        let mut class = intervals.iter().filter(|i| i.2 == change);
        let (mut cur, mut before) = (class.next().copied(), 0.0f32);
        for j in 0..count {
            // Stratified position in the class's intervals laid end to end.
            let u = (j as f32 + rng.next_f32()) / count as f32 * len;
            while let Some((a, b, _)) = cur {
                if u < before + (b - a) {
                    break;
                }
                before += b - a;
                match class.next().copied() {
                    Some(next) => cur = Some(next),
                    None => break,
                }
            }
            if let Some((a, b, _)) = cur {
                out.push((a + (u - before)).clamp(a, b));
            }
        }
    }
    out.sort_by(f32::total_cmp);
    out
}

/// The analytic importance of the Fig. 7 study (shared by its test and
/// `fogbank experiment visopt-fig7`): on a ray of length 10, importance 1
/// on [2, 2.05] and [7.01, 7.02] and ½ on [5, 5.3] — narrow peaks, the
/// thinnest a thousandth of the ray.
pub fn fig7_importance(t: f32) -> f32 {
    if (2.0..2.05).contains(&t) || (7.01..7.02).contains(&t) {
        1.0
    } else if (5.0..5.3).contains(&t) {
        0.5
    } else {
        0.0
    }
}

/// ∫₀¹⁰ k² of [`fig7_importance`], and ∫₀⁵ k².
pub const FIG7_EXACT: (f64, f64) = (0.05 + 0.3 * 0.25 + 0.01, 0.05);

#[cfg(test)]
mod sampling_test {
    use super::super::segments::{integral_at, merge};
    use super::*;

    use super::super::sampling::{fig7_importance as k, FIG7_EXACT};
    const EXACT: f64 = FIG7_EXACT.0;

    #[test]
    fn strata_are_sorted_inside_the_ray_and_one_per_stratum() {
        let mut rng = Pcg32::new(1, 2);
        let u = uniform(10.0, 64, &mut rng);
        for (j, t) in u.iter().enumerate() {
            let lo = j as f32 * 10.0 / 64.0;
            assert!(*t >= lo && *t <= lo + 10.0 / 64.0 + 1e-6);
        }
        let list = vec![
            Segment {
                t: 2.0,
                l: 1.0,
                k: 1.0,
                big_k: 0.0,
            },
            Segment {
                t: 6.0,
                l: 0.0,
                k: 0.0,
                big_k: 0.0,
            },
        ];
        let a = adaptive(&list, 10.0, 40, 0.5, &mut rng);
        assert_eq!(a.len(), 40);
        assert!(a.windows(2).all(|w| w[0] <= w[1]) && a[0] >= 0.0 && a[39] <= 10.0);
        // Half in the change-bracketing gaps [0, 2], [3, 6] and the end
        // [6, 10] (the end's neighbour 0 vs the border 0 still counts as
        // an end), half in the segment [2, 3].
        let in_segment = a.iter().filter(|&&t| (2.0..=3.0).contains(&t)).count();
        assert_eq!(in_segment, 20);
    }

    /// Fig. 7: K(z) converges to the exact ∫k² down to float precision, and
    /// K(5) becomes exact; the adaptive passes beat uniform ones. (When a
    /// sample first lands in a peak inside a long segment, the split turns
    /// the segment into points and the gap between them takes the mean
    /// importance, so the error jumps once before it shrinks, as the paper's
    /// split rule implies.)
    #[test]
    fn the_integral_converges_to_float_precision_on_narrow_peaks() {
        let (length, n) = (10.0f32, 64u32);
        let d = 2.0 * length / n as f32;
        let run = |adaptive_passes: bool, passes: usize| -> (f64, f64) {
            let mut rng = Pcg32::new(7, 3);
            let (mut list, mut next) = (Vec::new(), Vec::new());
            let mut kz = 0.0;
            for pass in 0..passes {
                let ts = if pass == 0 || !adaptive_passes {
                    uniform(length, n, &mut rng)
                } else {
                    adaptive(&list, length, n, 0.5, &mut rng)
                };
                let samples: Vec<(f32, f32)> = ts.iter().map(|&t| (t, k(t))).collect();
                kz = merge(&list, &samples, d, length, &mut next);
                std::mem::swap(&mut list, &mut next);
                assert!(
                    list.windows(2).all(|w| w[1].t >= w[0].right() - 1e-5),
                    "overlap"
                );
            }
            let at5 = integral_at(&list, kz, length, 5.0) as f64;
            ((kz as f64 - EXACT).abs() / EXACT, (at5 - 0.05).abs())
        };
        let (e4, _) = run(true, 4);
        let (e4_uniform, _) = run(false, 4);
        let (e40, at5) = run(true, 40);
        // After 1 + 3 passes the thinnest peak (width 0.01 of 10) is
        // usually still unfound: 7.4 % of the integral.
        assert!(
            e4 < 0.1,
            "1 uniform + 3 adaptive passes: relative error {e4}"
        );
        assert!(e4 < e4_uniform, "adaptive {e4} vs uniform {e4_uniform}");
        // Float-limited: change points near t = 7 resolve to 5e-7.
        assert!(e40 < 2e-5, "40 passes: relative error {e40}");
        assert!(at5 < 1e-6, "K(5) off by {at5}");
    }
}

//! Reservoir resampling on a 1D integral ∫_0^1 F, F(x) = x + 0.2: streaming
//! keeps candidates in proportion to their weights, RIS is unbiased, a
//! Talbot-weighted combination of reservoirs with different targets and
//! sources is unbiased, and the plain 1/M combination (Eq. 9) is not — the
//! failure the Talbot weights exist to prevent.

use fogbank_math::Pcg32;
use fogbank_render::integrators::restir::reservoir::{
    pairwise_canonical, pairwise_neighbour, stream_input, talbot, Reservoir,
};

const EXACT: f64 = 0.5 + 0.2;

fn f(x: f32) -> f32 {
    x + 0.2
}

/// Mean and standard error.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

#[test]
fn streaming_keeps_candidates_in_proportion_to_their_weights() {
    let w = [0.5f32, 2.0, 0.0, 1.0, 4.5, f32::NAN];
    let total: f32 = 8.0;
    let n = 200_000;
    let mut counts = [0u32; 6];
    let mut rng = Pcg32::new(5, 1);
    for _ in 0..n {
        let mut r = Reservoir::default();
        for (i, &wi) in w.iter().enumerate() {
            r.stream(i, wi, 1.0, rng.next_f32());
        }
        assert_eq!(r.w_sum, total);
        counts[r.y.unwrap()] += 1;
    }
    for (i, &wi) in w.iter().enumerate() {
        let p = if wi.is_finite() {
            (wi / total) as f64
        } else {
            0.0
        };
        let se = (p * (1.0 - p) / n as f64).sqrt();
        let f = counts[i] as f64 / n as f64;
        assert!(
            (f - p).abs() <= 4.0 * se + 1e-9,
            "candidate {i}: {f} vs {p}"
        );
    }
}

/// One RIS reservoir of `m` uniform candidates on [lo, hi) with target
/// `p_hat`.
fn ris(rng: &mut Pcg32, m: u32, lo: f32, hi: f32, p_hat: impl Fn(f32) -> f32) -> Reservoir<f32> {
    let mut r = Reservoir::default();
    for _ in 0..m {
        let x = lo + (hi - lo) * rng.next_f32();
        let p = 1.0 / (hi - lo);
        let ph = p_hat(x);
        r.stream(x, ph / p, ph, rng.next_f32());
        r.count(1.0);
    }
    r
}

#[test]
fn ris_is_unbiased() {
    let mut rng = Pcg32::new(7, 3);
    let est: Vec<f64> = (0..200_000)
        .map(|_| {
            // A target close to F but not equal to it.
            let r = ris(&mut rng, 4, 0.0, 1.0, |x| 0.5 + x * x);
            r.y.map_or(0.0, |y| (f(y) * r.contribution_weight()) as f64)
        })
        .collect();
    let (m, se) = mean_se(&est);
    assert!((m - EXACT).abs() < 4.0 * se, "{m} ± {se} vs {EXACT}");
}

/// Pixel q: target F on [0, 1), uniform source. Neighbour q': target F only
/// on [0, ½) and a source on [0, ½) alone, so it never proposes the upper
/// half. Returns F(y)·W of the combined reservoir.
fn combined(rng: &mut Pcg32, talbot_weights: bool) -> f64 {
    let p_hat_q = |x: f32| f(x);
    let p_hat_n = |x: f32| if x < 0.5 { f(x) } else { 0.0 };
    let inputs = [
        ris(rng, 4, 0.0, 1.0, p_hat_q),
        ris(rng, 4, 0.0, 0.5, p_hat_n),
    ];
    let m: Vec<f32> = inputs.iter().map(|r| r.m).collect();
    let m_total: f32 = m.iter().sum();
    let mut out = Reservoir::default();
    for (i, r) in inputs.iter().enumerate() {
        let Some(x) = r.y else { continue };
        let w_i = r.contribution_weight();
        let mis = if talbot_weights {
            talbot(i, &m, &[p_hat_q(x), p_hat_n(x)])
        } else {
            // Eq. 9: every input weighs M_i / ΣM whatever its support.
            r.m / m_total
        };
        stream_input(&mut out, x, w_i, mis, m_total, p_hat_q(x), rng.next_f32());
    }
    out.count(m_total);
    out.y
        .map_or(0.0, |y| (f(y) * out.contribution_weight()) as f64)
}

#[test]
fn talbot_combination_is_unbiased_and_plain_weights_are_not() {
    let mut rng = Pcg32::new(11, 5);
    let talbot_est: Vec<f64> = (0..200_000).map(|_| combined(&mut rng, true)).collect();
    let (m, se) = mean_se(&talbot_est);
    assert!(
        (m - EXACT).abs() < 4.0 * se,
        "Talbot: {m} ± {se} vs {EXACT}"
    );
    let plain: Vec<f64> = (0..200_000).map(|_| combined(&mut rng, false)).collect();
    let (m, se) = mean_se(&plain);
    assert!(
        (m - EXACT).abs() > 8.0 * se,
        "plain 1/M weights should be biased here: {m} ± {se} vs {EXACT}"
    );
}

/// Pairwise MIS's weights of one path x, as every input would give them,
/// sum to 1 wherever the receiving pixel's target p̂_0(x) > 0, for any
/// confidences M and targets (zeros included).
#[test]
fn pairwise_weights_sum_to_one() {
    let mut rng = Pcg32::new(3, 9);
    for case in 0..10_000 {
        let n = 2 + case % 5;
        let m: Vec<f32> = (0..n).map(|_| 0.5 + 20.0 * rng.next_f32()).collect();
        let p: Vec<f32> = (0..n)
            .map(|j| {
                let zero = j > 0 && rng.next_f32() < 0.3;
                if zero {
                    0.0
                } else {
                    1e-3 + 5.0 * rng.next_f32()
                }
            })
            .collect();
        let sum = pairwise_canonical(&m, &p)
            + (1..n)
                .map(|i| pairwise_neighbour(i, &m, p[i], p[0]))
                .sum::<f32>();
        assert!((sum - 1.0).abs() < 1e-5, "{m:?} {p:?}: {sum}");
    }
    assert_eq!(pairwise_canonical(&[4.0], &[0.3]), 1.0, "no neighbours");
}

/// Pixel q (target F on [0, 1)) combines with two neighbours that cover
/// only part of it — one proposes [0, ½) only, the other [¼, 1) with
/// another target — by pairwise MIS: the estimate is unbiased.
#[test]
fn pairwise_combination_is_unbiased() {
    let mut rng = Pcg32::new(17, 2);
    let p_hat_q = |x: f32| f(x);
    let p_hat_a = |x: f32| if x < 0.5 { f(x) } else { 0.0 };
    let p_hat_b = |x: f32| if x >= 0.25 { 0.3 + x } else { 0.0 };
    let targets = [&p_hat_q as &dyn Fn(f32) -> f32, &p_hat_a, &p_hat_b];
    let est: Vec<f64> = (0..200_000)
        .map(|_| {
            let inputs = [
                ris(&mut rng, 4, 0.0, 1.0, p_hat_q),
                ris(&mut rng, 2, 0.0, 0.5, p_hat_a),
                ris(&mut rng, 8, 0.25, 1.0, p_hat_b),
            ];
            let m: Vec<f32> = inputs.iter().map(|r| r.m).collect();
            let m_total: f32 = m.iter().sum();
            let mut out = Reservoir::default();
            for (i, r) in inputs.iter().enumerate() {
                let Some(x) = r.y else { continue };
                let mis = if i == 0 {
                    let at: Vec<f32> = targets.iter().map(|t| t(x)).collect();
                    pairwise_canonical(&m, &at)
                } else {
                    pairwise_neighbour(i, &m, targets[i](x), p_hat_q(x))
                };
                let w_i = r.contribution_weight();
                stream_input(&mut out, x, w_i, mis, m_total, p_hat_q(x), rng.next_f32());
            }
            out.count(m_total);
            out.y
                .map_or(0.0, |y| (f(y) * out.contribution_weight()) as f64)
        })
        .collect();
    let (m, se) = mean_se(&est);
    assert!(
        (m - EXACT).abs() < 4.0 * se,
        "pairwise: {m} ± {se} vs {EXACT}"
    );
}

#[test]
fn cap_and_retarget_keep_the_contribution_weight_consistent() {
    let mut r = Reservoir::default();
    r.stream(0.3f32, 2.0, 0.5, 0.0);
    r.count(40.0);
    let w = r.contribution_weight();
    r.cap(16.0);
    assert_eq!(r.m, 16.0);
    assert!((r.contribution_weight() - w).abs() < 1e-6 * w);
    let w_sum = r.w_sum;
    r.retarget(0.25);
    assert_eq!(
        (r.p_hat, r.w_sum),
        (0.25, 0.5 * w_sum),
        "w_sum scales with p̂"
    );
    assert!(
        (r.contribution_weight() - w).abs() < 1e-6 * w,
        "W is unchanged"
    );
    r.retarget(0.0);
    assert_eq!(r.contribution_weight(), 0.0);
    assert_eq!(Reservoir::<f32>::default().contribution_weight(), 0.0);
}

/// Spatial neighbours: inside the radius, never the pixel itself, and
/// uniform over the disk (radial CDF r²/R², angle uniform) across pixels.
#[test]
fn spatial_neighbours_are_uniform_in_the_disk() {
    use fogbank_render::integrators::restir::neighbours::{neighbour_offset, r2};
    let radius = 10.0f32;
    let (mut inner, mut right, mut n) = (0u32, 0u32, 0u32);
    for pixel in 0..20_000u32 {
        for k in 0..3 {
            let [dx, dy] = neighbour_offset(pixel, 7, k, radius);
            assert_ne!([dx, dy], [0, 0]);
            let r2d = (dx * dx + dy * dy) as f32;
            assert!(r2d.sqrt() <= radius + 0.75, "{dx} {dy}");
            n += 1;
            // Rounded to pixels, so compare coarse statistics: half the
            // area lies within R/√2, half the angles on the right.
            if r2d < 0.5 * radius * radius {
                inner += 1;
            }
            if dx > 0 {
                right += 1;
            }
        }
    }
    let frac = |c: u32| c as f64 / n as f64;
    assert!((frac(inner) - 0.5).abs() < 0.03, "inner {}", frac(inner));
    assert!((frac(right) - 0.5).abs() < 0.03, "right {}", frac(right));
    // R2 is well spread: its first points differ.
    assert_ne!(r2(0), r2(1));
    assert!(r2(5).iter().all(|x| (0.0..1.0).contains(x)));
}

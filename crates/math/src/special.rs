//! Numerics the chi-square harness rests on: adaptive Simpson quadrature
//! for expected bin counts and the regularised incomplete gamma function
//! for p-values.

use std::f64::consts::PI;

/// Simpson's rule on [a, b] refined where the halves disagree with the
/// whole (Lyness' criterion |S₂ − S| ≤ 15 ε with Richardson correction; ε
/// halves with each level so the total error stays within `tolerance`).
///
/// * It always refines to 16 panels first, so that a feature wider than
///   1/16 of the interval (one bright environment-map pixel inside a bin)
///   cannot hide between the five points of a single Simpson panel; narrower
///   features (the lobe of a g = 0.999 phase function) may be missed.
/// * A panel also stops once |S₂ − S| ≤ 15·10⁻⁴ |S₂|. A relative error r
///   of the expected counts biases Pearson's statistic by about r²N, which
///   for r = 10⁻⁴ stays below 1 up to N = 10⁸ samples; and integrands
///   evaluated through f32 directions carry ~10⁻⁷ of rounding noise that a
///   purely absolute tolerance would chase down to the maximum depth
///   everywhere (2^depth evaluations).
/// * It stops 16 levels deep, so that a jump discontinuity (a pixel edge),
///   where S₂ − S never shrinks relative to S₂, costs O(16) evaluations and
///   leaves an error below 2⁻¹⁶ of the interval times the jump, well inside
///   the relative tolerance of an enclosing integral.
pub fn adaptive_simpson(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, tolerance: f64) -> f64 {
    const MIN_DEPTH: u32 = 4;
    const MAX_DEPTH: u32 = 16;
    const RELATIVE: f64 = 1e-4;
    /// An interval [a, b] with f at its ends and midpoint and its Simpson
    /// estimate.
    #[derive(Clone, Copy)]
    struct Panel {
        a: f64,
        b: f64,
        fa: f64,
        fm: f64,
        fb: f64,
        whole: f64,
    }
    fn refine(f: &mut impl FnMut(f64) -> f64, p: Panel, tolerance: f64, depth: u32) -> f64 {
        let Panel {
            a,
            b,
            fa,
            fm,
            fb,
            whole,
        } = p;
        let m = 0.5 * (a + b);
        let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
        let (flm, frm) = (f(lm), f(rm));
        let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
        let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
        let halves = left + right;
        let delta = halves - whole;
        let converged = delta.abs() <= 15.0 * tolerance.max(RELATIVE * halves.abs());
        if depth >= MAX_DEPTH || (depth >= MIN_DEPTH && converged) {
            return halves + delta / 15.0;
        }
        let (l, r) = (
            Panel {
                a,
                b: m,
                fa,
                fm: flm,
                fb: fm,
                whole: left,
            },
            Panel {
                a: m,
                b,
                fa: fm,
                fm: frm,
                fb,
                whole: right,
            },
        );
        refine(f, l, 0.5 * tolerance, depth + 1) + refine(f, r, 0.5 * tolerance, depth + 1)
    }
    let (fa, fm, fb) = (f(a), f(0.5 * (a + b)), f(b));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    let p = Panel {
        a,
        b,
        fa,
        fm,
        fb,
        whole,
    };
    refine(f, p, tolerance, 0)
}

/// Gauss–Legendre quadrature on [0, 1] with `n` points: (node, weight)
/// pairs, the nodes the roots of the Legendre polynomial P_n found by
/// Newton's method from Chebyshev guesses (exact for polynomials of degree
/// below 2n).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * (x + 1.0), 0.5 * w)
        })
        .collect()
}

/// ln Γ(x) for x > 0 by the Lanczos approximation with g = 7 and nine
/// coefficients (Lanczos 1964; the coefficient set popularised by Press et
/// al. and Wikipedia), using the reflection formula below ½; relative error
/// about 1e-15.
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Γ(x) Γ(1 − x) = π / sin(πx)
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut sum = C[0];
    for (i, &c) in C.iter().enumerate().skip(1) {
        sum += c / (x + i as f64);
    }
    let t = x + G + 0.5;
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// Regularised lower incomplete gamma function P(a, x) = γ(a, x) / Γ(a).
pub fn gamma_p(a: f64, x: f64) -> f64 {
    1.0 - gamma_q(a, x)
}

/// Regularised upper incomplete gamma function Q(a, x) = Γ(a, x) / Γ(a),
/// the survival function of the gamma distribution: the chi-square p-value
/// of statistic s with k degrees of freedom is Q(k/2, s/2).
///
/// Follows the classic split (Press et al., Numerical Recipes §6.2): for
/// x < a + 1 the power series of γ(a, x) converges fast and Q = 1 − P; beyond
/// it the continued fraction of Γ(a, x) does, evaluated by the modified Lentz
/// method. Both carry the common factor e^(−x) x^a / Γ(a), formed in logs.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    assert!(a > 0.0, "gamma_q: a = {a} must be positive");
    if x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    if x == f64::INFINITY {
        return 0.0;
    }
    let log_prefactor = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        (1.0 - lower_series(a, x, log_prefactor)).clamp(0.0, 1.0)
    } else {
        upper_continued_fraction(a, x, log_prefactor).clamp(0.0, 1.0)
    }
}

/// P(a, x) from γ(a, x) = e^(−x) x^a Σₙ xⁿ / (a (a+1) ⋯ (a+n)).
fn lower_series(a: f64, x: f64, log_prefactor: f64) -> f64 {
    let mut term = 1.0 / a;
    let mut sum = term;
    let mut ap = a;
    for _ in 0..100_000 {
        ap += 1.0;
        term *= x / ap;
        sum += term;
        if term.abs() < sum.abs() * 1e-16 {
            break;
        }
    }
    sum * log_prefactor.exp()
}

/// Q(a, x) from the continued fraction
/// Γ(a, x) = e^(−x) x^a · 1/(x+1−a− 1·(1−a)/(x+3−a− 2·(2−a)/(x+5−a− ⋯))),
/// evaluated front to back with Lentz's method (tiny values stand in for
/// zero denominators).
fn upper_continued_fraction(a: f64, x: f64, log_prefactor: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..100_000 {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        if d.abs() < TINY {
            d = TINY;
        }
        c = b + an / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < 1e-16 {
            break;
        }
    }
    log_prefactor.exp() * h
}

#[cfg(test)]
mod special_test {
    use super::*;

    /// n points integrate x^k on [0, 1] exactly for k < 2n; weights sum to 1.
    #[test]
    fn gauss_legendre_is_exact_for_low_degrees() {
        for n in [1, 2, 5, 32, 128] {
            let q = gauss_legendre(n);
            for k in 0..(2 * n).min(40) {
                let sum: f64 = q.iter().map(|(x, w)| w * x.powi(k as i32)).sum();
                assert!(
                    (sum - 1.0 / (k as f64 + 1.0)).abs() < 1e-12,
                    "n {n} k {k}: {sum}"
                );
            }
        }
    }
}

//! Random variates, the normal CDF, and the six hypothetical distributions of
//! optical-depth estimates of Peters 2025 Fig. 2, each parameterised by its mean
//! τ and standard deviation σ so that all six share both.
//!
//! Every distribution also exposes its moment-generating function
//! M(s) = E(e^{sX}) at complex s. With it the expectations in Fig. 2 are
//! exact rather than simulated: for i.i.d. X0, X1 the naive estimate has
//! E(e^{−X̄}) = M(−½)², and since cos(S)e^{−X̄} = Re e^{−(1+i)X0/2} e^{−(1−i)X1/2},
//! the jackknife estimate (Eq. 4) has E(K) = |M(−(1+i)/2)|² and
//! E(K²) = ½(M(−1)² + |M(−1−i)|²). For the Laplace distribution this gives
//! E(K) = T / (1 + b⁴/4) < T, the slight underestimate the paper reports.

use fogbank_estimators::jackknife_function::Complex;
use fogbank_math::Pcg32;
use std::f64::consts::{PI, SQRT_2};

/// A standard normal variate (Box–Muller; the sine half is discarded so that
/// every call consumes exactly two uniforms).
#[inline]
pub fn standard_normal(rng: &mut Pcg32) -> f64 {
    let u1 = 1.0 - rng.next_f64();
    let u2 = rng.next_f64();
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// A standard exponential variate.
#[inline]
pub fn standard_exponential(rng: &mut Pcg32) -> f64 {
    -(1.0 - rng.next_f64()).ln()
}

/// Φ(x), via erfc with |error| < 1.2·10⁻⁷ (Numerical Recipes' Chebyshev
/// fit), ample for Kolmogorov–Smirnov distances of 10⁶ samples (~10⁻³).
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * erfc(-x / SQRT_2)
}

fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.26551223
            + t * (1.00002368
                + t * (0.37409196
                    + t * (0.09678418
                        + t * (-0.18628806
                            + t * (0.27886807
                                + t * (-1.13520398
                                    + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))
            .exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// Density of N(mean, std²).
pub fn normal_pdf(x: f64, mean: f64, std: f64) -> f64 {
    let z = (x - mean) / std;
    (-0.5 * z * z).exp() / (std * (2.0 * PI).sqrt())
}

/// The distribution families of Peters 2025 Fig. 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    Normal,
    Uniform,
    /// Shifted so that mean and standard deviation can be set independently.
    Exponential,
    Laplace,
    /// Shape 4 (skewness 1), shifted like the exponential.
    Gamma,
    /// Unshifted: its skewness grows with σ/τ.
    Lognormal,
}

pub const FAMILIES: [Family; 6] = [
    Family::Normal,
    Family::Uniform,
    Family::Exponential,
    Family::Laplace,
    Family::Gamma,
    Family::Lognormal,
];

const GAMMA_SHAPE: u32 = 4;

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::Normal => "normal",
            Family::Uniform => "uniform",
            Family::Exponential => "exponential",
            Family::Laplace => "laplace",
            Family::Gamma => "gamma",
            Family::Lognormal => "lognormal",
        }
    }
}

/// One member of a family with mean `tau` and standard deviation `sigma`.
#[derive(Clone, Copy, Debug)]
pub struct Distribution {
    pub family: Family,
    pub tau: f64,
    pub sigma: f64,
}

impl Distribution {
    pub fn new(family: Family, tau: f64, sigma: f64) -> Self {
        Distribution { family, tau, sigma }
    }

    fn lognormal_params(&self) -> (f64, f64) {
        let s2 = (1.0 + (self.sigma / self.tau).powi(2)).ln();
        (self.tau.ln() - 0.5 * s2, s2.sqrt())
    }

    #[inline]
    pub fn sample(&self, rng: &mut Pcg32) -> f64 {
        let (tau, sigma) = (self.tau, self.sigma);
        match self.family {
            Family::Normal => tau + sigma * standard_normal(rng),
            Family::Uniform => tau + sigma * 3f64.sqrt() * (2.0 * rng.next_f64() - 1.0),
            Family::Exponential => tau - sigma + sigma * standard_exponential(rng),
            Family::Laplace => {
                let e = standard_exponential(rng) * sigma / SQRT_2;
                if rng.next_u32() & 1 == 0 {
                    tau + e
                } else {
                    tau - e
                }
            }
            Family::Gamma => {
                let theta = sigma / (GAMMA_SHAPE as f64).sqrt();
                let g: f64 = (0..GAMMA_SHAPE).map(|_| standard_exponential(rng)).sum();
                tau - GAMMA_SHAPE as f64 * theta + theta * g
            }
            Family::Lognormal => {
                let (mu, s) = self.lognormal_params();
                (mu + s * standard_normal(rng)).exp()
            }
        }
    }

    /// M(s) = E(e^{sX}) for Re s ≤ 0 (all families have it there).
    pub fn mgf(&self, s: Complex) -> Complex {
        let (tau, sigma) = (self.tau, self.sigma);
        let one = Complex::new(1.0, 0.0);
        let e = |z: Complex| z.exp();
        match self.family {
            Family::Normal => e(s.scale(tau).add(s.mul(s).scale(0.5 * sigma * sigma))),
            Family::Uniform => {
                let a = sigma * 3f64.sqrt();
                if s.re == 0.0 && s.im == 0.0 {
                    return one;
                }
                let num = e(s.scale(tau + a)).add(e(s.scale(tau - a)).scale(-1.0));
                num.div(s.scale(2.0 * a))
            }
            Family::Exponential => e(s.scale(tau - sigma)).div(one.add(s.scale(-sigma))),
            Family::Laplace => {
                let b = sigma / SQRT_2;
                e(s.scale(tau)).div(one.add(s.mul(s).scale(-b * b)))
            }
            Family::Gamma => {
                let k = GAMMA_SHAPE as f64;
                let theta = sigma / k.sqrt();
                let base = one.add(s.scale(-theta));
                let mut p = one;
                for _ in 0..GAMMA_SHAPE {
                    p = p.mul(base);
                }
                e(s.scale(tau - k * theta)).div(p)
            }
            Family::Lognormal => {
                // No closed form: trapezoid rule over z ~ N(0, 1); the
                // integrand is bounded (Re s ≤ 0) and smooth.
                let (mu, sd) = self.lognormal_params();
                let (n, lim) = (8000, 12.0);
                let h = 2.0 * lim / n as f64;
                let mut acc = Complex::new(0.0, 0.0);
                for k in 0..=n {
                    let z = -lim + k as f64 * h;
                    let w = if k == 0 || k == n { 0.5 } else { 1.0 };
                    let x = (mu + sd * z).exp();
                    acc = acc.add(e(s.scale(x)).scale(w * normal_pdf(z, 0.0, 1.0) * h));
                }
                acc
            }
        }
    }

    /// Exact (mean, std) of the jackknife estimate cos(S)e^{−X̄} (Eq. 4) for
    /// two i.i.d. draws.
    pub fn jackknife_moments(&self) -> (f64, f64) {
        let m1 = abs2(self.mgf(Complex::new(-0.5, -0.5)));
        let a = self.mgf(Complex::new(-1.0, 0.0)).re;
        let m2 = 0.5 * (a * a + abs2(self.mgf(Complex::new(-1.0, -1.0))));
        (m1, (m2 - m1 * m1).max(0.0).sqrt())
    }

    /// Exact (mean, std) of the naive estimate e^{−X̄} for two i.i.d. draws.
    pub fn naive_moments(&self) -> (f64, f64) {
        let h = self.mgf(Complex::new(-0.5, 0.0)).re;
        let a = self.mgf(Complex::new(-1.0, 0.0)).re;
        let m1 = h * h;
        (m1, (a * a - m1 * m1).max(0.0).sqrt())
    }
}

fn abs2(z: Complex) -> f64 {
    z.re * z.re + z.im * z.im
}

/// Kolmogorov–Smirnov distance of `sorted` to the normal distribution with
/// the sample's own mean and standard deviation (the Lilliefors statistic).
pub fn ks_normal(sorted: &[f64], mean: f64, std: f64) -> f64 {
    let n = sorted.len() as f64;
    sorted
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let f = normal_cdf((x - mean) / std);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

/// Anderson–Darling A² of `sorted` against the fitted normal; weights the
/// tails, where the jackknife's sensitivity to non-normality lies.
pub fn anderson_darling_normal(sorted: &[f64], mean: f64, std: f64) -> f64 {
    let n = sorted.len();
    let clamp = |p: f64| p.clamp(1e-300, 1.0 - 1e-16);
    let s: f64 = (0..n)
        .map(|i| {
            let a = clamp(normal_cdf((sorted[i] - mean) / std));
            let b = clamp(normal_cdf((sorted[n - 1 - i] - mean) / std));
            (2 * i + 1) as f64 * (a.ln() + (1.0 - b).ln())
        })
        .sum();
    -(n as f64) - s / n as f64
}

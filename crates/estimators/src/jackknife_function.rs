//! Jackknife estimation of functions of optical depth (Peters 2025 §5.1): for
//! two i.i.d. normal estimates X0, X1 of τ, Re g(X̄ + iS) is an unbiased
//! estimate of g(τ) for entire g (Eq. 7); the MIS weights of App. F; and the
//! UMVU estimate of e^{−τ} for m ≥ 2 estimates (Eq. 3).

/// A complex number, just enough for Eq. 7.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Complex {
    pub re: f64,
    pub im: f64,
}

// Named methods rather than operator traits keep call sites explicit about
// complex arithmetic in the real-valued estimator code.
#[allow(clippy::should_implement_trait)]
impl Complex {
    pub fn new(re: f64, im: f64) -> Self {
        Complex { re, im }
    }
    pub fn exp(self) -> Self {
        let r = self.re.exp();
        Complex::new(r * self.im.cos(), r * self.im.sin())
    }
    pub fn mul(self, o: Self) -> Self {
        Complex::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    pub fn div(self, o: Self) -> Self {
        let d = o.re * o.re + o.im * o.im;
        Complex::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    pub fn scale(self, s: f64) -> Self {
        Complex::new(self.re * s, self.im * s)
    }
    pub fn add(self, o: Self) -> Self {
        Complex::new(self.re + o.re, self.im + o.im)
    }
}

/// Peters 2025, Eq. 7: Re g(X̄ + iS), X̄ = (X0 + X1)/2, S = |X0 − X1|/2.
pub fn estimate_function(g: impl Fn(Complex) -> Complex, x0: f64, x1: f64) -> f64 {
    g(Complex::new(0.5 * (x0 + x1), 0.5 * (x0 - x1).abs())).re
}

/// Peters 2025, App. F: the jackknife estimate of (a e^{−τ} + b)/(c e^{−τ} + d)
/// as Re[(a T̃ + b)/(c T̃ + d)] with T̃ = e^{−X̄}(cos S − i sin S), computed as
/// Re(num · conj(den)) / |den|².
pub fn mis_weight(a: f64, b: f64, c: f64, d: f64, x0: f64, x1: f64) -> f64 {
    let (xbar, s) = (0.5 * (x0 + x1), 0.5 * (x0 - x1).abs());
    let e = (-xbar).exp();
    let t = Complex::new(e * s.cos(), -e * s.sin());
    let num = Complex::new(a * t.re + b, a * t.im);
    let den = Complex::new(c * t.re + d, c * t.im);
    let den2 = den.re * den.re + den.im * den.im;
    if den2 == 0.0 {
        return 0.0;
    }
    (num.re * den.re + num.im * den.im) / den2
}

/// Peters 2025, Eq. 3: the UMVU estimate of e^{−τ} from m ≥ 2 i.i.d. normal
/// estimates, Γ((m−1)/2)(2/S)^{(m−3)/2} J_{(m−3)/2}(S) e^{−X̄}. The Bessel
/// factor equals the confluent limit function ₀F₁(; (m−1)/2; −S²/4), an
/// entire series evaluated directly (m = 2 gives cos S, Eq. 4).
pub fn umvu_transmittance(x: &[f64]) -> f64 {
    let m = x.len();
    assert!(m >= 2, "Eq. 3 needs at least two estimates");
    let mean = x.iter().sum::<f64>() / m as f64;
    let s2 = (x.iter().map(|v| v * v).sum::<f64>() / m as f64 - mean * mean).max(0.0);
    let b = (m as f64 - 1.0) / 2.0;
    let z = -s2 / 4.0;
    let (mut term, mut sum) = (1.0f64, 1.0f64);
    for k in 0..200 {
        term *= z / ((k as f64 + 1.0) * (b + k as f64));
        sum += term;
        if term.abs() < 1e-17 * sum.abs().max(1e-300) {
            break;
        }
    }
    sum * (-mean).exp()
}

#[cfg(test)]
mod jackknife_function_test {
    use super::*;

    #[test]
    fn eq7_special_cases() {
        for (x0, x1) in [(0.3f64, 1.7f64), (2.0, 2.0), (-0.5, 4.0), (5.0, 0.1)] {
            let (xbar, s) = (0.5 * (x0 + x1), 0.5f64 * (x0 - x1).abs());
            let t = estimate_function(|z| z.scale(-1.0).exp(), x0, x1);
            assert!((t - s.cos() * (-xbar).exp()).abs() < 1e-12);
            let inv = estimate_function(|z| Complex::new(1.0, 0.0).div(z), x0, x1);
            let expected = (x0 + x1) / (x0 * x0 + x1 * x1);
            assert!(
                (inv - expected).abs() < 1e-12 * expected.abs().max(1.0),
                "{inv} vs {expected}"
            );
        }
    }

    #[test]
    fn umvu_m2_is_eq4() {
        for (x0, x1) in [(0.3f64, 1.7f64), (1.0, 1.0), (3.0, 0.2)] {
            let k = umvu_transmittance(&[x0, x1]);
            let eq4 = (0.5f64 * (x0 - x1).abs()).cos() * (-0.5 * (x0 + x1)).exp();
            assert!((k - eq4).abs() < 1e-12);
        }
    }

    #[test]
    fn app_f_weights_sum_to_one() {
        // w0 = p0/(p0 + T), w1 = T/(p0 + T) as (a T + b)/(c T + d).
        let mut rng = fogbank_math::Pcg32::new(2, 9);
        for _ in 0..10_000 {
            let x0 = rng.next_f64() * 8.0 - 1.0;
            let x1 = rng.next_f64() * 8.0 - 1.0;
            let p0 = rng.next_f64() * 3.0;
            let w0 = mis_weight(0.0, p0, 1.0, p0, x0, x1);
            let w1 = mis_weight(1.0, 0.0, 1.0, p0, x0, x1);
            assert!((w0 + w1 - 1.0).abs() < 1e-9, "{w0} + {w1}");
        }
    }
}

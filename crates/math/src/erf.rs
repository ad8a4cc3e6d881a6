//! The error function, its complement and its inverse in f32, written so
//! that WGSL (`microfacet.wgsl`) can repeat them line by line: the Beckmann
//! microfacet distribution's masking term and visible-normal sampler need
//! them on both backends.

/// erfc(x) = 1 − erf(x) by the Chebyshev fit of Press et al. (Numerical
/// Recipes, 2nd ed., §6.2, `erfcc`): fractional error below 1.2·10⁻⁷
/// everywhere, so that tails such as erfc(4) ≈ 1.5·10⁻⁸ keep their digits.
pub fn erfc(x: f32) -> f32 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -1.265_512_2
        + t * (1.000_023_7
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_204
                                + t * (1.488_515_9 + t * (-0.822_152_2 + t * 0.170_872_77))))))));
    let r = t * (-z * z + poly).exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// erf(x) = 1 − erfc(x).
pub fn erf(x: f32) -> f32 {
    1.0 - erfc(x)
}

/// erf⁻¹(x) on (−1, 1) by Giles' single-precision approximation
/// ("Approximating the erfinv function", GPU Computing Gems, 2010):
/// relative error of a few 10⁻⁷; ±∞ at ±1.
pub fn erfinv(x: f32) -> f32 {
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        let w = w - 2.5;
        let mut p = 2.810_226_4e-8;
        p = 3.432_739_4e-7 + p * w;
        p = -3.523_387_7e-6 + p * w;
        p = -4.391_506_5e-6 + p * w;
        p = 2.185_808_7e-4 + p * w;
        p = -1.253_725e-3 + p * w;
        p = -4.177_681_6e-3 + p * w;
        p = 0.246_640_73 + p * w;
        1.501_409_4 + p * w
    } else {
        let w = w.sqrt() - 3.0;
        let mut p = -2.002_142_6e-4;
        p = 1.009_505_6e-4 + p * w;
        p = 1.349_343_2e-3 + p * w;
        p = -3.673_428_4e-3 + p * w;
        p = 5.739_507_7e-3 + p * w;
        p = -7.622_461_3e-3 + p * w;
        p = 9.438_870_5e-3 + p * w;
        p = 1.001_674 + p * w;
        2.832_976_8 + p * w
    };
    p * x
}

#[cfg(test)]
mod erf_test {
    use super::*;

    /// Against the series erf(x) = 2/√π Σ (−1)ⁿ x^(2n+1) / (n! (2n+1)) in
    /// f64, and erfc's tail against its asymptotic expansion.
    #[test]
    fn erf_matches_its_series_and_erfc_its_tail() {
        for i in -300..=300 {
            let x = i as f64 / 100.0;
            let (mut term, mut sum) = (x, x);
            for n in 1..200 {
                term *= -x * x / n as f64;
                sum += term / (2 * n + 1) as f64;
            }
            let want = sum * 2.0 / std::f64::consts::PI.sqrt();
            assert!((erf(x as f32) as f64 - want).abs() < 2e-7, "erf({x})");
        }
        for x in [3.5f64, 4.0, 5.0, 6.0] {
            let s = 1.0 - 1.0 / (2.0 * x * x) + 3.0 / (4.0 * x.powi(4)) - 15.0 / (8.0 * x.powi(6));
            let want = (-x * x).exp() / (x * std::f64::consts::PI.sqrt()) * s;
            let rel = (erfc(x as f32) as f64 - want).abs() / want;
            assert!(rel < 2e-3, "erfc({x}): {} vs {want}", erfc(x as f32));
        }
    }

    #[test]
    fn erfinv_inverts_erf() {
        for i in -999..=999 {
            let y = i as f32 / 1000.0;
            let x = erfinv(y);
            assert!((erf(x) - y).abs() < 3e-6, "erf(erfinv({y})) = {}", erf(x));
        }
    }
}

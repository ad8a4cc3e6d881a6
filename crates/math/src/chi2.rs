//! Chi-square goodness-of-fit tests of sampling routines against their pdfs.
//!
//! A sampler and the pdf it claims must agree, or every estimator that
//! divides by that pdf is biased. Following Mitsuba 3's `ChiSquareTest`
//! (Jakob et al.), the domain is cut into bins, samples are counted per bin,
//! the pdf is integrated numerically over each bin to get the expected
//! counts, bins expecting fewer than [`MIN_EXPECTED`] samples are pooled (the
//! chi-square approximation of Pearson's statistic is poor below about five
//! expected counts), and the p-value of Pearson's statistic comes from the
//! chi-square distribution with (bins − 1) degrees of freedom.
//!
//! Two domains are supported: an interval `[a, b]` (distance sampling, with a
//! separate bin for "no sample", e.g. a photon that escapes the medium) and
//! the unit sphere in (cos θ, φ) coordinates about +z, whose rectangular bins
//! all have the same solid angle.
//!
//! Tests are deterministic (a fixed PCG32 seed) and reject at
//! [`SIGNIFICANCE`]; when one test file runs several tests, each should use
//! the Šidák-corrected level [`sidak`] so that the file as a whole keeps a
//! 1 % false-alarm rate.

use crate::rng::Pcg32;
use glam::DVec3;
use std::f64::consts::PI;
use std::fmt;

pub use crate::special::{adaptive_simpson, gamma_p, gamma_q, ln_gamma};

/// Default significance level of a single test.
pub const SIGNIFICANCE: f64 = 0.01;

/// Bins expecting fewer samples than this are pooled into one bin: Pearson's
/// statistic is only chi-square distributed when expected counts are not
/// small (the usual rule of thumb, also used by Mitsuba 3).
pub const MIN_EXPECTED: f64 = 5.0;

/// Number of worst bins printed by [`Chi2Result`]'s `Display`.
const TABLE_ROWS: usize = 12;

/// Šidák correction: the per-test level that gives a family of `tests`
/// independent tests an overall false-rejection probability `alpha`
/// (Šidák 1967): 1 − (1 − α)^(1/n).
pub fn sidak(alpha: f64, tests: u32) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests.max(1) as f64)
}

/// Outcome of one chi-square test.
#[derive(Clone, Debug)]
pub struct Chi2Result {
    /// Pearson's statistic Σ (observed − expected)² / expected over the
    /// pooled bins; infinite when a sample fell where the pdf is zero or
    /// outside the domain.
    pub statistic: f64,
    /// Number of pooled bins minus one (the sample count is fixed).
    pub dof: usize,
    /// Probability that a correct sampler gives a statistic at least this
    /// large: Q(dof / 2, statistic / 2).
    pub p_value: f64,
    /// Number of samples drawn.
    pub samples: usize,
    /// Integral of the pdf over the domain plus the escape probability; 1
    /// for a normalised pdf (reported because a wrong normalisation is the
    /// most common bug).
    pub total_probability: f64,
    /// Samples that were non-finite, outside the domain, or (on the sphere)
    /// not of unit length.
    pub invalid_samples: usize,
    /// Samples that fell in a bin whose integrated pdf is exactly zero.
    pub impossible_samples: usize,
    /// The bins with the largest contributions to the statistic, worst first,
    /// as a printable table.
    pub table: String,
}

impl Chi2Result {
    /// For tests: prints the result and panics unless the pdf integrates to
    /// 1 within `tolerance` and the sampler passes at level `alpha`.
    pub fn assert_passes(&self, alpha: f64, tolerance: f64, label: &str) {
        println!("{label}{self}");
        assert!(
            (self.total_probability - 1.0).abs() < tolerance,
            "{label}{self}"
        );
        assert!(self.passes(alpha), "{label}{self}");
    }

    /// True when the sampler is not rejected at level `alpha`.
    pub fn passes(&self, alpha: f64) -> bool {
        self.p_value >= alpha
    }
}

impl fmt::Display for Chi2Result {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "chi-square: statistic {:.3}, dof {}, p-value {:.4e}, {} samples, \
             total probability {:.6}, {} invalid and {} impossible samples",
            self.statistic,
            self.dof,
            self.p_value,
            self.samples,
            self.total_probability,
            self.invalid_samples,
            self.impossible_samples
        )?;
        write!(f, "{}", self.table)
    }
}

/// One bin before pooling.
struct Bin {
    label: String,
    observed: f64,
    expected: f64,
}

/// Test of a sampler on the interval `[a, b]`.
#[derive(Clone, Debug)]
pub struct IntervalTest {
    pub a: f64,
    pub b: f64,
    pub bins: usize,
    pub samples: usize,
    pub seed: u64,
}

impl IntervalTest {
    /// `sample` returns a point of `[a, b]` or `None` ("no sample", e.g. the
    /// photon escaped); `pdf` is the density of the returned points (so it
    /// integrates to 1 − `none_probability` over `[a, b]`), and
    /// `none_probability` is the probability of `None`, which gets its own
    /// bin.
    pub fn run(
        &self,
        sample: impl FnMut(&mut Pcg32) -> Option<f64>,
        pdf: impl Fn(f64) -> f64,
        none_probability: f64,
    ) -> Chi2Result {
        assert!(self.b > self.a && self.bins > 0 && self.samples > 0);
        let n = self.bins;
        let width = (self.b - self.a) / n as f64;
        let rng = Pcg32::new(self.seed, 0x5851_f42d);
        let tally = Tally::draw(self.samples, rng, n, sample, |x| {
            (x.is_finite() && x >= self.a && x <= self.b)
                .then(|| (((x - self.a) / width) as usize).min(n - 1))
        });
        // Integration error is budgeted in expected counts: a thousandth of
        // a sample per bin is far below the Poisson noise of any bin.
        let tolerance = 1e-3 / self.samples as f64;
        let mut bins = Vec::with_capacity(n + 1);
        for (i, &obs) in tally.observed.iter().enumerate() {
            let x0 = self.a + i as f64 * width;
            let x1 = if i + 1 == n { self.b } else { x0 + width };
            let mass = adaptive_simpson(&mut |x| pdf(x), x0, x1, tolerance);
            bins.push(Bin {
                label: format!("x ∈ [{x0:.5}, {x1:.5}]"),
                observed: obs,
                expected: mass * self.samples as f64,
            });
        }
        tally.evaluate(bins, none_probability, self.samples)
    }
}

/// Test of a direction sampler on the unit sphere, binned in (cos θ, φ)
/// about +z: cos θ = z and φ = atan2(y, x) ∈ [0, 2π). Rectangles in these
/// coordinates have solid angle Δcos θ · Δφ (Archimedes), so equal-size bins
/// have equal solid angle and the pdf in solid angle integrates directly.
#[derive(Clone, Debug)]
pub struct SphereTest {
    pub cos_theta_bins: usize,
    pub phi_bins: usize,
    pub samples: usize,
    pub seed: u64,
}

impl SphereTest {
    /// `bins` = [cos θ bins, φ bins].
    pub fn new(bins: [usize; 2], samples: usize, seed: u64) -> SphereTest {
        SphereTest {
            cos_theta_bins: bins[0],
            phi_bins: bins[1],
            samples,
            seed,
        }
    }

    /// `sample` returns a unit direction or `None` (no sample, e.g. a black
    /// environment map); `pdf` is in solid angle and `none_probability` is
    /// the probability of `None`.
    pub fn run(
        &self,
        sample: impl FnMut(&mut Pcg32) -> Option<DVec3>,
        pdf: impl Fn(DVec3) -> f64,
        none_probability: f64,
    ) -> Chi2Result {
        let (nz, np) = (self.cos_theta_bins, self.phi_bins);
        assert!(nz > 0 && np > 0 && self.samples > 0);
        let dz = 2.0 / nz as f64;
        let dphi = 2.0 * PI / np as f64;
        let rng = Pcg32::new(self.seed, 0xda3e_39cb);
        let tally = Tally::draw(self.samples, rng, nz * np, sample, |d| {
            if !(d.is_finite() && (d.length() - 1.0).abs() < 1e-3) {
                return None;
            }
            let z = d.z.clamp(-1.0, 1.0);
            let mut phi = d.y.atan2(d.x);
            if phi < 0.0 {
                phi += 2.0 * PI;
            }
            let iz = (((z + 1.0) / dz) as usize).min(nz - 1);
            let ip = ((phi / dphi) as usize).min(np - 1);
            Some(iz * np + ip)
        });
        let tolerance = 1e-3 / self.samples as f64;
        let direction = |z: f64, phi: f64| {
            let s = (1.0 - z * z).max(0.0).sqrt();
            DVec3::new(s * phi.cos(), s * phi.sin(), z)
        };
        let mut bins = Vec::with_capacity(nz * np + 1);
        for iz in 0..nz {
            let z0 = -1.0 + iz as f64 * dz;
            let z1 = if iz + 1 == nz { 1.0 } else { z0 + dz };
            for ip in 0..np {
                let p0 = ip as f64 * dphi;
                let p1 = if ip + 1 == np { 2.0 * PI } else { p0 + dphi };
                // Nested adaptive Simpson: the inner tolerance is scaled so
                // that its error, integrated over z, stays within budget.
                let inner_tolerance = 0.1 * tolerance / (z1 - z0);
                let mass = adaptive_simpson(
                    &mut |z| {
                        adaptive_simpson(&mut |phi| pdf(direction(z, phi)), p0, p1, inner_tolerance)
                    },
                    z0,
                    z1,
                    tolerance,
                );
                bins.push(Bin {
                    label: format!("cosθ ∈ [{z0:+.4}, {z1:+.4}], φ ∈ [{p0:.4}, {p1:.4}]"),
                    observed: tally.observed[iz * np + ip],
                    expected: mass * self.samples as f64,
                });
            }
        }
        tally.evaluate(bins, none_probability, self.samples)
    }
}

/// Observed counts of a sampler: per bin, without a sample, and invalid.
struct Tally {
    observed: Vec<f64>,
    none: f64,
    invalid: usize,
}

impl Tally {
    /// Draws `samples` samples with `rng`; `bin_of` places a sample in one
    /// of `bins` bins, or returns `None` when the sample is invalid.
    fn draw<T>(
        samples: usize,
        mut rng: Pcg32,
        bins: usize,
        mut sample: impl FnMut(&mut Pcg32) -> Option<T>,
        bin_of: impl Fn(T) -> Option<usize>,
    ) -> Tally {
        let mut tally = Tally {
            observed: vec![0.0f64; bins],
            none: 0.0,
            invalid: 0,
        };
        for _ in 0..samples {
            match sample(&mut rng).map(&bin_of) {
                None => tally.none += 1.0,
                Some(Some(i)) => tally.observed[i] += 1.0,
                Some(None) => tally.invalid += 1,
            }
        }
        tally
    }

    /// Adds the "no sample" bin to `bins` and evaluates the test.
    fn evaluate(&self, mut bins: Vec<Bin>, none_probability: f64, samples: usize) -> Chi2Result {
        bins.push(Bin {
            label: "no sample".into(),
            observed: self.none,
            expected: none_probability * samples as f64,
        });
        evaluate(bins, samples, self.invalid)
    }
}

/// Pools small bins, computes the statistic and its p-value, and formats the
/// worst bins.
fn evaluate(bins: Vec<Bin>, samples: usize, invalid: usize) -> Chi2Result {
    let total_probability = bins.iter().map(|b| b.expected).sum::<f64>() / samples as f64;
    let impossible: f64 = bins
        .iter()
        .filter(|b| b.expected <= 0.0)
        .map(|b| b.observed)
        .sum();

    // Contribution of each raw bin, for the table only.
    let mut rows: Vec<(f64, &Bin)> = bins
        .iter()
        .filter(|b| b.expected > 0.0 || b.observed > 0.0)
        .map(|b| {
            let c = if b.expected > 0.0 {
                (b.observed - b.expected).powi(2) / b.expected
            } else {
                f64::INFINITY
            };
            (c, b)
        })
        .collect();
    rows.sort_by(|x, y| y.0.total_cmp(&x.0));
    let mut table = format!(
        "{:>12} {:>12} {:>12}  bin\n",
        "observed", "expected", "(o−e)²/e"
    );
    for (c, b) in rows.iter().take(TABLE_ROWS) {
        table += &format!(
            "{:>12.0} {:>12.2} {:>12.3}  {}\n",
            b.observed, b.expected, c, b.label
        );
    }

    let result = |statistic: f64, dof: usize, p_value: f64| Chi2Result {
        statistic,
        dof,
        p_value,
        samples,
        total_probability,
        invalid_samples: invalid,
        impossible_samples: impossible as usize,
        table: table.clone(),
    };
    if invalid > 0 || impossible > 0.0 {
        return result(f64::INFINITY, 0, 0.0);
    }

    // Pool every bin expecting fewer than MIN_EXPECTED samples into one; if
    // the pool itself is still too small it joins the smallest regular bin.
    let mut regular: Vec<(f64, f64)> = Vec::new();
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    for b in bins.iter().filter(|b| b.expected > 0.0) {
        if b.expected < MIN_EXPECTED {
            pool_obs += b.observed;
            pool_exp += b.expected;
        } else {
            regular.push((b.observed, b.expected));
        }
    }
    if pool_exp >= MIN_EXPECTED {
        regular.push((pool_obs, pool_exp));
    } else if pool_exp > 0.0 {
        match regular.iter_mut().min_by(|x, y| x.1.total_cmp(&y.1)) {
            Some(smallest) => {
                smallest.0 += pool_obs;
                smallest.1 += pool_exp;
            }
            None => regular.push((pool_obs, pool_exp)),
        }
    }
    if regular.len() < 2 {
        // A single bin carries no information about the shape of the pdf.
        return result(0.0, 0, 1.0);
    }
    let statistic: f64 = regular.iter().map(|&(o, e)| (o - e) * (o - e) / e).sum();
    let dof = regular.len() - 1;
    let p_value = gamma_q(0.5 * dof as f64, 0.5 * statistic);
    result(statistic, dof, p_value)
}

#[cfg(test)]
mod chi2_unit_test {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-300)
    }

    #[test]
    fn ln_gamma_matches_factorials_and_half_integers() {
        let mut factorial = 1.0f64;
        for n in 1..30 {
            // Γ(n) = (n − 1)!
            assert!((ln_gamma(n as f64) - factorial.ln()).abs() < 1e-12);
            factorial *= n as f64;
        }
        // Γ(½) = √π, Γ(3/2) = √π / 2, Γ(0.1) = 9.513507698668731836…
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-14);
        assert!((ln_gamma(1.5) - (0.5 * PI.sqrt()).ln()).abs() < 1e-14);
        assert!(close(ln_gamma(0.1).exp(), 9.513_507_698_668_73, 1e-13));
    }

    #[test]
    fn gamma_q_matches_closed_forms() {
        // Q(1, x) = e^(−x); Q(n, x) = e^(−x) Σ_{k<n} x^k / k! for integer n.
        for &x in &[1e-3, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0, 80.0] {
            assert!(close(gamma_q(1.0, x), (-x).exp(), 1e-13), "x = {x}");
            for n in 2..12 {
                let mut term = 1.0;
                let mut sum = 0.0;
                for k in 0..n {
                    if k > 0 {
                        term *= x / k as f64;
                    }
                    sum += term;
                }
                let q = (-x).exp() * sum;
                let got = gamma_q(n as f64, x);
                assert!(
                    (got - q).abs() <= 1e-13 * q + 1e-15,
                    "Q({n}, {x}) = {got}, expected {q}"
                );
            }
        }
    }

    #[test]
    fn gamma_q_matches_reference_values() {
        // Q(½, x) = erfc(√x); erfc values to 16 digits (mpmath).
        assert!(close(gamma_q(0.5, 1.0), 0.157_299_207_050_285_13, 1e-13));
        assert!(close(gamma_q(0.5, 4.0), 0.004_677_734_981_047_266, 1e-12));
        assert!(close(gamma_q(0.5, 0.25), 0.479_500_122_186_953_5, 1e-13));
        assert!(close(
            gamma_q(0.5, 25.0),
            1.537_459_794_428_034_8e-12,
            1e-10
        ));
        // Upper 1 % points of the chi-square distribution (mpmath): the
        // p-value there must be 0.01 for 1, 10, 100 and 1000 dof.
        for &(dof, x) in &[
            (1.0, 6.634_896_601_021_215),
            (10.0, 23.209_251_158_954_36),
            (100.0, 135.806_723_171_026_8),
            (1000.0, 1_106.968_994_352_217_4),
        ] {
            let p = gamma_q(0.5 * dof, 0.5 * x);
            assert!(close(p, 0.01, 1e-9), "dof {dof}: p = {p}");
        }
        // Q(3.7, 2.2) and P(0.3, 0.05) (mpmath gammainc, regularized).
        assert!(close(gamma_q(3.7, 2.2), 0.770_232_691_203_556_8, 1e-12));
        assert!(close(gamma_p(0.3, 0.05), 0.448_436_862_106_592_8, 1e-12));
        assert_eq!(gamma_q(2.0, 0.0), 1.0);
        assert_eq!(gamma_q(2.0, f64::INFINITY), 0.0);
    }

    #[test]
    fn sidak_level_composes_to_alpha() {
        let a = sidak(0.01, 4);
        assert!(close(1.0 - (1.0 - a).powi(4), 0.01, 1e-12));
        assert!(close(sidak(0.01, 1), 0.01, 1e-12));
    }

    #[test]
    fn adaptive_simpson_handles_smooth_and_jump_integrands() {
        let exact = 1.0 - (-3.0f64).exp();
        let got = adaptive_simpson(&mut |x| (-x).exp(), 0.0, 3.0, 1e-12);
        assert!((got - exact).abs() < 1e-8, "{got}");
        // A step at an irrational point: error bounded by the finest panel.
        let s = 1.0 / 3.0f64.sqrt();
        let got = adaptive_simpson(&mut |x| if x < s { 1.0 } else { 3.0 }, 0.0, 1.0, 1e-9);
        assert!((got - (s + 3.0 * (1.0 - s))).abs() < 1e-5, "{got}");
    }
}

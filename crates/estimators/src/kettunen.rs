//! Kettunen et al. 2021, "An Unbiased Ray-Marching Transmittance Estimator":
//! the sample budget N_CMF from the control optical depth, the biased
//! estimate exp(−X), and the unbiased power-series estimator with aggressive
//! Russian roulette and U-statistics (parameters from the notes).

use crate::optical_depth::{estimates, prepare, Importance, Jitter, MAX_ESTIMATES};
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::VolumeAccess;

/// N_CMF = ceil(cbrt((τ̄ + 0.015)(τ̄ + 0.65)(τ̄ + 60.3))) for control optical
/// depth τ̄.
pub fn n_cmf(tau_bar: f64) -> u32 {
    ((tau_bar + 0.015) * (tau_bar + 0.65) * (tau_bar + 60.3))
        .cbrt()
        .ceil()
        .max(1.0) as u32
}

/// Expected number of estimates per unbiased call, 1 + Σ_{k≥1} P(N ≥ k).
pub const EXPECTED_ESTIMATES: f64 = 1.31945;
/// Highest series degree; the truncation bias is negligible.
pub const MAX_DEGREE: usize = MAX_ESTIMATES - 1;

/// P(N ≥ k) for k = 0 … 8: 1; then 0.1 (p_Z = 0.9) for k = 1, 2 (K = 2);
/// then P(N ≥ k−1) · min(1, c/k) with c = 2.
pub fn survival() -> [f64; MAX_DEGREE + 1] {
    let mut p = [0.0; MAX_DEGREE + 1];
    p[0] = 1.0;
    for k in 1..=MAX_DEGREE {
        p[k] = if k <= 2 {
            0.1
        } else {
            p[k - 1] * (2.0 / k as f64).min(1.0)
        };
    }
    p
}

/// Samples the series degree N with `P(N ≥ k) = survival()[k]`.
pub fn sample_degree(u: f64, survival: &[f64; MAX_DEGREE + 1]) -> usize {
    (1..=MAX_DEGREE)
        .take_while(|&k| u < survival[k])
        .last()
        .unwrap_or(0)
}

/// The U-statistic of the notes: for each pivot i, elementary symmetric means
/// m_k of y_j = X_i − X_j (j ≠ i), T = 1/(N+1) Σ_i e^{−X_i} Σ_k m_k / (k! P(N ≥ k)).
pub fn u_statistic(x: &[f64], survival: &[f64; MAX_DEGREE + 1]) -> f64 {
    let n = x.len() - 1;
    let mut total = 0.0;
    for i in 0..x.len() {
        let mut m = [0.0f64; MAX_DEGREE + 1];
        m[0] = 1.0;
        let mut count = 0usize;
        for (j, &xj) in x.iter().enumerate() {
            if j == i {
                continue;
            }
            let y = x[i] - xj;
            // Stable online update of elementary symmetric means when y
            // joins `count` earlier values, highest degree first.
            for k in (1..=count + 1).rev() {
                m[k] += k as f64 / (count + 1) as f64 * (m[k - 1] * y - m[k]);
            }
            count += 1;
        }
        let mut series = 0.0;
        let mut factorial = 1.0;
        for k in 0..=n {
            if k > 0 {
                factorial *= k as f64;
            }
            series += m[k] / (factorial * survival[k]);
        }
        total += (-x[i]).exp() * series;
    }
    total / x.len() as f64
}

/// `biased_ray_marching`: mean-importance stratified sampling with N_CMF
/// samples (doubled on request), T = exp(−X).
pub fn biased_transmittance<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    doubled: bool,
    rng: &mut Pcg32,
) -> Estimate {
    let prep = prepare(v, seg, Importance::Mean);
    if prep.total <= 0.0 {
        return Estimate::ONE;
    }
    let n = n_cmf(prep.total) * if doubled { 2 } else { 1 };
    let mut lookups = 0;
    let mut x = [0.0; 1];
    estimates(
        v,
        &prep,
        prep.total / n as f64,
        Jitter::Stratified,
        rng,
        &mut lookups,
        &mut x,
    );
    Estimate {
        transmittance: (-x[0]).exp() as f32,
        lookups,
    }
}

/// `unbiased_ray_marching`: N + 1 i.i.d. estimates of
/// max(1, round(mult · N_CMF / 1.31945)) samples each, combined by the
/// U-statistic. May exceed 1 or be negative; never clamped.
pub fn unbiased_transmittance<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    mult: u32,
    rng: &mut Pcg32,
) -> Estimate {
    let prep = prepare(v, seg, Importance::Mean);
    if prep.total <= 0.0 {
        return Estimate::ONE;
    }
    let per = ((mult.max(1) as f64 * n_cmf(prep.total) as f64 / EXPECTED_ESTIMATES).round() as u32)
        .max(1);
    let surv = survival();
    let degree = sample_degree(rng.next_f64(), &surv);
    let mut x = [0.0; MAX_ESTIMATES];
    let x = &mut x[..degree + 1];
    let mut lookups = 0;
    estimates(
        v,
        &prep,
        prep.total / per as f64,
        Jitter::Stratified,
        rng,
        &mut lookups,
        x,
    );
    Estimate {
        transmittance: u_statistic(x, &surv) as f32,
        lookups,
    }
}

#[cfg(test)]
mod kettunen_test {
    use super::*;

    #[test]
    fn expected_extra_estimates_match_the_notes() {
        let s = survival();
        // 0.31945 is the uncapped series; the cap at degree 8 drops a tail of
        // P(N ≥ 9) + … ≈ 8e-5.
        let extra: f64 = s[1..].iter().sum();
        assert!((extra - (EXPECTED_ESTIMATES - 1.0)).abs() < 1e-4, "{extra}");
    }

    #[test]
    fn degree_sampling_follows_survival() {
        let s = survival();
        let n = 1_000_000;
        let mut counts = [0usize; MAX_DEGREE + 1];
        let mut rng = Pcg32::new(4, 4);
        for _ in 0..n {
            counts[sample_degree(rng.next_f64(), &s)] += 1;
        }
        for k in 1..=MAX_DEGREE {
            let p: f64 = counts[k..].iter().sum::<usize>() as f64 / n as f64;
            let se = (s[k] * (1.0 - s[k]) / n as f64).sqrt();
            assert!(
                (p - s[k]).abs() < 4.0 * se + 1e-9,
                "P(N≥{k}) = {p} vs {}",
                s[k]
            );
        }
    }

    #[test]
    fn u_statistic_is_unbiased_for_gaussian_inputs() {
        // E[T] = e^{−τ} for any i.i.d. unbiased X (the series is exact up to
        // the negligible truncation at degree 8).
        let s = survival();
        let mut rng = Pcg32::new(8, 1);
        let (tau, sigma) = (1.3f64, 0.6f64);
        let normal = |rng: &mut Pcg32| {
            let (u1, u2) = (1.0 - rng.next_f64(), rng.next_f64());
            (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
        };
        let n = 400_000;
        let (mut sum, mut sum2) = (0.0, 0.0);
        for _ in 0..n {
            let d = sample_degree(rng.next_f64(), &s);
            let x: Vec<f64> = (0..=d).map(|_| tau + sigma * normal(&mut rng)).collect();
            let t = u_statistic(&x, &s);
            sum += t;
            sum2 += t * t;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!(
            (mean - (-tau).exp()).abs() < 4.0 * se,
            "{mean} vs {} (se {se})",
            (-tau).exp()
        );
    }
}

//! Peters 2025 Fig. 3 and App. A: relative RMSE of the jackknife estimate
//! (Eq. 4) and of the naive e^{−X̄} for m = 2 normal optical-depth estimates
//! of standard deviation σ, simulated and in closed form:
//! jackknife sqrt((e^{σ²} − 1)/2) (App. A.2), naive
//! sqrt(e^{σ²} − 2e^{σ²/4} + 1) (App. A.1 with the variance of X̄ halved).
//! Their ratio is ≥ 1 and tends to √2.
//!
//! Both estimates are evaluated on the same draws, so the simulated ratio is
//! far less noisy than either rRMSE.

use super::distributions::standard_normal;
use crate::harness::trials::run_chunked;
use crate::harness::Writer;
use fogbank_estimators::jackknife::jackknife_transmittance;
use fogbank_eval::plot::{palette, Corner, Figure, LinePlot, Rgb, Series};

pub const DEFAULT_TRIALS: u64 = 1_000_000;
const SEED: u32 = 0x000f_1603;
/// The rRMSE does not depend on τ; any value will do.
const TAU: f64 = 1.0;

/// Simulated σ values. Beyond σ ≈ 2 the fourth moments that govern the
/// Monte Carlo error of an MSE grow like e^{2σ²} and 10⁶ trials no longer
/// pin the rRMSE down; the closed forms cover the rest.
pub fn sigmas() -> Vec<f64> {
    (1..=20).map(|k| k as f64 * 0.1).collect()
}

pub fn jackknife_rrmse(sigma: f64) -> f64 {
    ((sigma * sigma).exp_m1() / 2.0).sqrt()
}

pub fn naive_rrmse(sigma: f64) -> f64 {
    let s2 = sigma * sigma;
    // e^{s²} − 2e^{s²/4} + 1 = expm1(s²) − 2 expm1(s²/4), without cancellation.
    (s2.exp_m1() - 2.0 * (s2 / 4.0).exp_m1()).sqrt()
}

#[derive(Clone, Copy, Debug)]
pub struct Point {
    pub sigma: f64,
    pub jackknife: f64,
    pub naive: f64,
}

impl Point {
    pub fn ratio(&self) -> f64 {
        self.naive / self.jackknife
    }
}

/// Simulated rRMSE at each σ from `trials` pairs.
pub fn compute(trials: u64, sigmas: &[f64]) -> Vec<Point> {
    let t = (-TAU).exp();
    sigmas
        .iter()
        .enumerate()
        .map(|(k, &sigma)| {
            let (sj, sn) = run_chunked(
                trials,
                SEED,
                k as u32,
                || (0.0f64, 0.0f64),
                |rng, acc, n| {
                    for _ in 0..n {
                        let x0 = TAU + sigma * standard_normal(rng);
                        let x1 = TAU + sigma * standard_normal(rng);
                        acc.0 += (jackknife_transmittance(x0, x1) - t).powi(2);
                        acc.1 += ((-0.5 * (x0 + x1)).exp() - t).powi(2);
                    }
                },
                |a, b| {
                    a.0 += b.0;
                    a.1 += b.1;
                },
            );
            Point {
                sigma,
                jackknife: (sj / trials as f64).sqrt() / t,
                naive: (sn / trials as f64).sqrt() / t,
            }
        })
        .collect()
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let trials = trials.unwrap_or(DEFAULT_TRIALS);
    let pts = compute(trials, &sigmas());
    let rows: Vec<Vec<String>> = pts
        .iter()
        .map(|p| {
            vec![
                format!("{:.2}", p.sigma),
                format!("{:.6}", p.jackknife),
                format!("{:.6}", jackknife_rrmse(p.sigma)),
                format!("{:.6}", p.naive),
                format!("{:.6}", naive_rrmse(p.sigma)),
                format!("{:.6}", p.ratio()),
                format!("{:.6}", naive_rrmse(p.sigma) / jackknife_rrmse(p.sigma)),
            ]
        })
        .collect();
    w.csv(
        "fig3.csv",
        &[
            "sigma",
            "jackknife_rrmse_sim",
            "jackknife_rrmse_exact",
            "naive_rrmse_sim",
            "naive_rrmse_exact",
            "ratio_sim",
            "ratio_exact",
        ],
        &rows,
    )?;
    let dense: Vec<f64> = (1..=300).map(|k| k as f64 * 0.01).collect();
    let curve = |f: &dyn Fn(f64) -> f64| dense.iter().map(|&s| (s, f(s))).collect::<Vec<_>>();
    let fig = Figure::new(2)
        .title(format!(
            "Peters 2025 Fig. 3: rRMSE for normal optical depth, m = 2 (lines App. A, dots {trials} trials)"
        ))
        .with(
            LinePlot::new("rRMSE", "sigma", "relative RMSE")
                .log_y()
                .legend(Corner::UpperLeft)
                .with(Series::line("jackknife sqrt((e^s2-1)/2)", curve(&jackknife_rrmse), palette(0)))
                .with(Series::points("", pts.iter().map(|p| (p.sigma, p.jackknife)).collect(), palette(0)))
                .with(Series::line("naive sqrt(e^s2-2e^(s2/4)+1)", curve(&naive_rrmse), palette(1)))
                .with(Series::points("", pts.iter().map(|p| (p.sigma, p.naive)).collect(), palette(1))),
        )
        .with(
            LinePlot::new("ratio naive / jackknife", "sigma", "rRMSE ratio")
                .legend(Corner::LowerRight)
                .y_range(0.95, 1.5)
                .with(Series::line("App. A", curve(&|s| naive_rrmse(s) / jackknife_rrmse(s)), palette(2)))
                .with(Series::points("simulated", pts.iter().map(|p| (p.sigma, p.ratio())).collect(), palette(2)))
                .with(Series::dashed("sqrt(2)", vec![(0.0, 2f64.sqrt()), (3.0, 2f64.sqrt())], Rgb::GREY)),
        );
    w.figure("fig3", &fig)?;
    let last = pts[pts.len() - 1];
    let max_dev = pts
        .iter()
        .map(|p| {
            (p.jackknife / jackknife_rrmse(p.sigma) - 1.0)
                .abs()
                .max((p.naive / naive_rrmse(p.sigma) - 1.0).abs())
        })
        .fold(0.0, f64::max);
    let min_ratio = pts.iter().map(|p| p.ratio()).fold(f64::INFINITY, f64::min);
    Ok(format!(
        "For X0, X1 ~ N(τ, σ²) the simulated rRMSEs ({trials} pairs per σ, σ = 0.1 … {:.1}) match the App. A \
closed forms within {:.1}% (largest relative deviation over both estimators and all σ). The ratio naive/jackknife \
is ≥ 1 everywhere (smallest simulated value {min_ratio:.4}, at σ = 0.1 where both are ≈ σ/√2) and grows towards \
√2 = 1.4142: at σ = {:.1} it is {:.4} simulated, {:.4} exact; exact at σ = 3: {:.4}. This is the paper's Fig. 3: \
the jackknife is never worse and better by nearly √2 for large σ.",
        last.sigma,
        100.0 * max_dev,
        last.sigma,
        last.ratio(),
        naive_rrmse(last.sigma) / jackknife_rrmse(last.sigma),
        naive_rrmse(3.0) / jackknife_rrmse(3.0),
    ))
}

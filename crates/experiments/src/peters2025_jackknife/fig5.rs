//! Peters 2025 Fig. 5 (§4.1): convergence of optical-depth estimators on the
//! Fig. 4a-like profile, RMSE against the sample count N = 1 … 1000 on
//! log-log axes, for the deterministic midpoint rule, uniform jittered,
//! stratified jittered and i.i.d. uniform sampling, with fitted slopes.
//! The samplers are the few lines of §4.1 written out directly.

use super::profile::Profile1D;
use crate::harness::log_log_fit;
use crate::harness::trials::run_chunked;
use crate::harness::Writer;
use fogbank_eval::plot::{palette, Corner, Figure, LinePlot, Series};
use fogbank_math::Pcg32;

pub const DEFAULT_TRIALS: u64 = 10_000;
const SEED: u32 = 0x000f_1605;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampler {
    Midpoint,
    UniformJittered,
    StratifiedJittered,
    Iid,
}

pub const SAMPLERS: [Sampler; 4] = [
    Sampler::Midpoint,
    Sampler::UniformJittered,
    Sampler::StratifiedJittered,
    Sampler::Iid,
];

impl Sampler {
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Midpoint => "midpoint",
            Sampler::UniformJittered => "uniform jittered",
            Sampler::StratifiedJittered => "stratified jittered",
            Sampler::Iid => "i.i.d.",
        }
    }

    /// X = L/N Σ μ(t_j) with t_j per §4.1.
    #[inline]
    pub fn estimate(self, p: &Profile1D, n: u32, rng: &mut Pcg32) -> f64 {
        let l = p.len();
        let h = l / n as f64;
        let sum: f64 = match self {
            Sampler::Midpoint => (0..n).map(|j| p.sigma_t_at((j as f64 + 0.5) * h)).sum(),
            Sampler::UniformJittered => {
                let xi = rng.next_f64();
                (0..n).map(|j| p.sigma_t_at((j as f64 + xi) * h)).sum()
            }
            Sampler::StratifiedJittered => (0..n)
                .map(|j| p.sigma_t_at((j as f64 + rng.next_f64()) * h))
                .sum(),
            Sampler::Iid => (0..n).map(|_| p.sigma_t_at(rng.next_f64() * l)).sum(),
        };
        h * sum
    }
}

/// N = 1 … 1000, about six per decade.
pub fn sample_counts() -> Vec<u32> {
    vec![
        1, 2, 3, 5, 7, 10, 15, 20, 30, 50, 70, 100, 150, 200, 300, 500, 700, 1000,
    ]
}

#[derive(Clone, Debug)]
pub struct Curve {
    pub sampler: Sampler,
    /// (N, RMSE).
    pub rmse: Vec<(f64, f64)>,
    /// Least-squares slope of log RMSE over log N.
    pub slope: f64,
    pub intercept: f64,
}

pub fn compute(trials: u64, counts: &[u32]) -> (Vec<Curve>, f64) {
    let p = Profile1D::smooth();
    let tau = p.optical_depth();
    let curves = SAMPLERS
        .iter()
        .enumerate()
        .map(|(si, &s)| {
            let rmse: Vec<(f64, f64)> = counts
                .iter()
                .map(|&n| {
                    // The midpoint rule is deterministic: one evaluation.
                    let t = if s == Sampler::Midpoint { 1 } else { trials };
                    let sq = run_chunked(
                        t,
                        SEED,
                        (si as u32) << 16 | n,
                        || 0.0f64,
                        |rng, acc, count| {
                            for _ in 0..count {
                                *acc += (s.estimate(&p, n, rng) - tau).powi(2);
                            }
                        },
                        |a, b| *a += b,
                    );
                    (n as f64, (sq / t as f64).sqrt())
                })
                .collect();
            let (slope, intercept) = log_log_fit(&rmse);
            Curve {
                sampler: s,
                rmse,
                slope,
                intercept,
            }
        })
        .collect();
    (curves, tau)
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let trials = trials.unwrap_or(DEFAULT_TRIALS);
    let (curves, tau) = compute(trials, &sample_counts());
    let mut rows = Vec::new();
    for c in &curves {
        for &(n, e) in &c.rmse {
            rows.push(vec![
                c.sampler.name().to_string(),
                format!("{n}"),
                format!("{e:.6e}"),
            ]);
        }
    }
    w.csv("fig5.csv", &["sampler", "N", "rmse"], &rows)?;
    let mut plot = LinePlot::new(
        format!("tau = {tau:.4}, {trials} realisations per N"),
        "N (samples)",
        "RMSE",
    )
    .log_x()
    .log_y()
    .legend(Corner::LowerLeft);
    for (k, c) in curves.iter().enumerate() {
        plot = plot.with(Series::new(
            format!("{} (slope {:.2})", c.sampler.name(), c.slope),
            c.rmse.clone(),
            palette(k),
            fogbank_eval::plot::Mark::LinePoints,
        ));
    }
    let n0 = 1.0;
    let e0 = curves[3].rmse[0].1;
    plot = plot
        .with(Series::dashed(
            "1/N",
            vec![(n0, e0), (1000.0, e0 / 1000.0)],
            fogbank_eval::plot::Rgb::GREY,
        ))
        .with(Series::dashed(
            "",
            vec![(n0, e0), (1000.0, e0 / 1000f64.sqrt())],
            fogbank_eval::plot::Rgb::GREY,
        ));
    w.figure(
        "fig5",
        &Figure::new(1)
            .panel_size(760, 560)
            .title("Peters 2025 Fig. 5: convergence of optical-depth estimators")
            .with(plot),
    )?;
    let slopes: Vec<String> = curves
        .iter()
        .map(|c| format!("{} {:.2}", c.sampler.name(), c.slope))
        .collect();
    let at = |s: Sampler, n: f64| {
        curves
            .iter()
            .find(|c| c.sampler == s)
            .and_then(|c| c.rmse.iter().find(|p| p.0 == n))
            .map(|p| p.1)
            .unwrap_or(f64::NAN)
    };
    Ok(format!(
        "RMSE of optical-depth estimates on the Fig. 4a-like profile (exact τ = {tau:.5}) for N = 1 … 1000, {trials} \
realisations per N (one for the deterministic midpoint rule). Fitted log-log slopes over all N: {}. Stratified and \
uniform jittered sampling converge close to 1/N, i.i.d. sampling at 1/√N. Between N = 1 and 100 stratified and \
uniform jittered perform similarly (N = 10: {:.4} vs {:.4}; N = 100: {:.5} vs {:.5}); at N = 1000, where steps \
(2 voxels) reach the voxel scale, the equidistant techniques pull ahead (uniform jittered {:.2e}, midpoint {:.2e}, \
stratified {:.2e}). Paper (Fig. 5): stratified techniques closer to linear than to 1/√N convergence, stratified and \
uniform jittered similar for N ≤ 100, equidistant ones faster at voxel-scale steps.",
        slopes.join(", "),
        at(Sampler::StratifiedJittered, 10.0),
        at(Sampler::UniformJittered, 10.0),
        at(Sampler::StratifiedJittered, 100.0),
        at(Sampler::UniformJittered, 100.0),
        at(Sampler::UniformJittered, 1000.0),
        at(Sampler::Midpoint, 1000.0),
        at(Sampler::StratifiedJittered, 1000.0),
    ))
}

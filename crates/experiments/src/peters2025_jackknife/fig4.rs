//! Peters 2025 Figs. 4 and 6 (§4.1): distributions of ray-marching estimates
//! of optical depth with stratified jittered sampling (one independent
//! jitter per stratum) against uniform jittered sampling (one jitter shared
//! by all N equidistant samples), on a smooth profile (Fig. 4a-like) and a
//! sparse one (Fig. 6-like). The jackknife is unbiased only for normal
//! estimates; by the Lyapunov CLT (App. B) stratified sampling approaches a
//! normal distribution as N grows while uniform jittered sampling, a
//! function of one random number, does not. Each histogram gets a fitted
//! normal density and two normality statistics (KS distance to the fitted
//! normal, Anderson–Darling A²).

use super::distributions::{anderson_darling_normal, ks_normal, normal_pdf};
use super::profile::Profile1D;
use crate::harness::trials::run_chunked;
use crate::harness::Writer;
use fogbank_estimators::optical_depth::Jitter;
use fogbank_eval::plot::{palette, Figure, Histogram, LinePlot, Rgb, Series};

pub const DEFAULT_TRIALS: u64 = 1_000_000;
pub const SAMPLE_COUNTS: [u32; 3] = [5, 10, 20];
const SEED: u32 = 0x000f_1604;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Fig. 4: the smooth profile.
    Smooth,
    /// Fig. 6: the sparse profile.
    Sparse,
}

impl Variant {
    pub fn profile(self) -> Profile1D {
        match self {
            Variant::Smooth => Profile1D::smooth(),
            Variant::Sparse => Profile1D::sparse(),
        }
    }
    fn name(self) -> &'static str {
        match self {
            Variant::Smooth => "fig4",
            Variant::Sparse => "fig6",
        }
    }
}

pub fn jitter_name(j: Jitter) -> &'static str {
    match j {
        Jitter::Stratified => "stratified",
        Jitter::Uniform => "uniform",
    }
}

#[derive(Clone, Debug)]
pub struct Case {
    pub jitter: Jitter,
    pub n: u32,
    pub mean: f64,
    pub std: f64,
    /// Kolmogorov–Smirnov distance to the fitted normal.
    pub ks: f64,
    /// Anderson–Darling A² against the fitted normal.
    pub ad: f64,
    /// The sorted estimates.
    pub sorted: Vec<f64>,
}

/// `trials` optical-depth estimates per (jitter, N) from the project's
/// Alg. 1 with one super-voxel spanning the profile (plain jittered
/// sampling); returns the cases and the exact optical depth.
pub fn compute(trials: u64, variant: Variant, counts: &[u32]) -> (Vec<Case>, f64) {
    let profile = variant.profile();
    let marching = profile.marching();
    let mut cases = Vec::new();
    for (ji, jitter) in [Jitter::Stratified, Jitter::Uniform]
        .into_iter()
        .enumerate()
    {
        for &n in counts {
            let f_delta = marching.prep.total / n as f64;
            let mut sorted = run_chunked(
                trials,
                SEED ^ (variant as u32) << 8,
                (ji as u32) << 16 | n,
                Vec::new,
                |rng, acc: &mut Vec<f64>, count| {
                    let (mut x, mut lookups) = ([0.0f64], 0u32);
                    for _ in 0..count {
                        marching.estimates(f_delta, jitter, rng, &mut lookups, &mut x);
                        acc.push(x[0]);
                    }
                },
                |a, b| a.extend(b),
            );
            sorted.sort_by(f64::total_cmp);
            let len = sorted.len() as f64;
            let mean = sorted.iter().sum::<f64>() / len;
            let std = (sorted.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (len - 1.0)).sqrt();
            let (ks, ad) = if std > 0.0 {
                (
                    ks_normal(&sorted, mean, std),
                    anderson_darling_normal(&sorted, mean, std),
                )
            } else {
                (1.0, f64::INFINITY)
            };
            cases.push(Case {
                jitter,
                n,
                mean,
                std,
                ks,
                ad,
                sorted,
            });
        }
    }
    (cases, profile.optical_depth())
}

pub fn run(w: &mut Writer, trials: Option<u64>, variant: Variant) -> Result<String, String> {
    let trials = trials.unwrap_or(DEFAULT_TRIALS);
    let (cases, tau) = compute(trials, variant, &SAMPLE_COUNTS);
    let name = variant.name();
    write_csv(w, name, &cases, tau)?;
    histograms(w, &cases, trials, variant, tau)?;
    profile_figure(w, variant, tau)?;
    Ok(summary(&cases, trials, variant, tau))
}

/// `<name>.csv`: mean, std and the normality statistics per case.
fn write_csv(w: &mut Writer, name: &str, cases: &[Case], tau: f64) -> Result<(), String> {
    let rows: Vec<Vec<String>> = cases
        .iter()
        .map(|c| {
            vec![
                jitter_name(c.jitter).to_string(),
                c.n.to_string(),
                format!("{:.6}", c.mean),
                format!("{:.6}", c.std),
                format!("{:.6}", c.ks),
                format!("{:.2}", c.ad),
                format!("{:.6}", tau),
            ]
        })
        .collect();
    w.csv(
        &format!("{name}.csv"),
        &[
            "jitter",
            "N",
            "mean",
            "std",
            "ks_distance",
            "anderson_darling",
            "tau_exact",
        ],
        &rows,
    )
}

/// `<name>_histograms.csv` and the figure `<name>`: each case's histogram
/// with its fitted normal density, on a common range per N so stratified
/// and uniform compare.
fn histograms(
    w: &mut Writer,
    cases: &[Case],
    trials: u64,
    variant: Variant,
    tau: f64,
) -> Result<(), String> {
    let name = variant.name();
    let mut fig = Figure::new(SAMPLE_COUNTS.len()).title(format!(
        "Peters 2025 Fig. {}: histograms of {trials} optical-depth estimates (exact tau = {tau:.4}), fitted normal in black",
        if variant == Variant::Smooth { "4" } else { "6" }
    ));
    let mut hist_rows = Vec::new();
    for jitter in [Jitter::Stratified, Jitter::Uniform] {
        for c in cases.iter().filter(|c| c.jitter == jitter) {
            let partner: Vec<&Case> = cases.iter().filter(|d| d.n == c.n).collect();
            let lo = partner
                .iter()
                .map(|d| d.sorted[0])
                .fold(f64::INFINITY, f64::min);
            let hi = partner
                .iter()
                .map(|d| d.sorted[d.sorted.len() - 1])
                .fold(f64::NEG_INFINITY, f64::max);
            let (lo, hi) = (
                lo.max(tau - 5.0 * c.std.max(1e-9)),
                hi.min(tau + 5.0 * c.std.max(1e-9)),
            );
            let (lo, hi) = if hi > lo {
                (lo, hi)
            } else {
                (lo - 1.0, lo + 1.0)
            };
            let h = Histogram::density(
                format!("{} jittered, N = {}", jitter_name(jitter), c.n),
                "optical depth X",
                &c.sorted,
                100,
                (lo, hi),
            );
            for (k, v) in h.heights.iter().enumerate() {
                hist_rows.push(vec![
                    jitter_name(jitter).to_string(),
                    c.n.to_string(),
                    format!("{:.6}", h.edges[k]),
                    format!("{:.6}", h.edges[k + 1]),
                    format!("{:.6}", v),
                ]);
            }
            let curve: Vec<(f64, f64)> = (0..=200)
                .map(|k| lo + (hi - lo) * k as f64 / 200.0)
                .map(|x| (x, normal_pdf(x, c.mean, c.std)))
                .collect();
            fig = fig.with(
                h.overlay(Series::line("", curve, Rgb::BLACK))
                    .note(format!("KS = {:.4}", c.ks))
                    .note(format!("A2 = {:.1}", c.ad)),
            );
        }
    }
    w.csv(
        &format!("{name}_histograms.csv"),
        &["jitter", "N", "bin_lo", "bin_hi", "density"],
        &hist_rows,
    )?;
    w.figure(name, &fig)
}

/// `<name>_profile`: the extinction profile the estimates march.
fn profile_figure(w: &mut Writer, variant: Variant, tau: f64) -> Result<(), String> {
    let name = variant.name();
    let profile = variant.profile();
    let pts: Vec<(f64, f64)> = profile
        .values()
        .iter()
        .enumerate()
        .map(|(i, &v)| (i as f64 + 0.5, v))
        .collect();
    w.figure(
        &format!("{name}_profile"),
        &Figure::new(1).panel_size(900, 300).with(
            LinePlot::new(
                format!("extinction profile (tau = {tau:.4})"),
                "t (voxels)",
                "mu(t)",
            )
            .with(Series::line("", pts, palette(0))),
        ),
    )
}

/// The finding: KS distance and A² per N for both jitters.
fn summary(cases: &[Case], trials: u64, variant: Variant, tau: f64) -> String {
    let get = |j: Jitter, n: u32| {
        cases
            .iter()
            .find(|c| c.jitter == j && c.n == n)
            .expect("case")
    };
    let line = |j: Jitter| {
        SAMPLE_COUNTS
            .iter()
            .map(|&n| format!("N = {n}: KS {:.4}, A² {:.1}", get(j, n).ks, get(j, n).ad))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let finding = match variant {
        Variant::Smooth => "Stratified jittered estimates approach a normal distribution quickly as N grows, \
uniform jittered estimates do not (paper, Fig. 4: close to normal at N = 10 with stratified sampling, no sign of \
approaching normal at N = 20 with uniform jittered sampling).",
        Variant::Sparse => "On the sparse profile even stratified jittered sampling with N = 20 stays far from \
normal because only the few strata that contain a feature carry variance (paper, Fig. 6).",
    };
    format!(
        "{trials} optical-depth estimates per case on the {} profile (2048 voxels, exact τ = {tau:.5}), from the \
project's Alg. 1 with one super-voxel (plain jittered ray marching). Normality of each distribution against its fitted \
normal (Kolmogorov–Smirnov distance; Anderson–Darling A², 2.5 ≈ the 5% critical value): stratified — {}. Uniform \
jittered — {}. {finding}",
        if variant == Variant::Smooth { "smooth (Fig. 4a-like)" } else { "sparse (Fig. 6-like)" },
        line(Jitter::Stratified),
        line(Jitter::Uniform)
    )
}

//! Lerzer and Dachsbacher 2025 Fig. 7: how fast the importance segments converge. On the
//! analytic importance with narrow peaks ([`fig7_importance`]), the error
//! of K̃(z) = ∫ k̃² over the ray and of K̃(5) after each pass, one uniform
//! pass followed by adaptive ones (the paper's schedule, continued) against
//! uniform passes only; N = 64 samples per pass, d = 2L/N, averaged over
//! independent runs.

use crate::harness::Writer;
use fogbank_math::Pcg32;
use fogbank_render::integrators::visopt::sampling::{
    adaptive, fig7_importance, uniform, FIG7_EXACT,
};
use fogbank_render::integrators::visopt::segments::{integral_at, merge};

pub const DEFAULT_RUNS: u64 = 64;
const PASSES: usize = 40;
const LENGTH: f32 = 10.0;
const N: u32 = 64;

/// Per pass: (relative error of K(z), absolute error of K(5), entries).
fn run_once(adaptive_passes: bool, seed: u64) -> Vec<(f64, f64, usize)> {
    let mut rng = Pcg32::new(seed, 11);
    let d = 2.0 * LENGTH / N as f32;
    let (mut list, mut next) = (Vec::new(), Vec::new());
    (0..PASSES)
        .map(|pass| {
            let ts = if pass == 0 || !adaptive_passes {
                uniform(LENGTH, N, &mut rng)
            } else {
                adaptive(&list, LENGTH, N, 0.5, &mut rng)
            };
            let samples: Vec<(f32, f32)> = ts.iter().map(|&t| (t, fig7_importance(t))).collect();
            let kz = merge(&list, &samples, d, LENGTH, &mut next);
            std::mem::swap(&mut list, &mut next);
            let at5 = integral_at(&list, kz, LENGTH, 5.0) as f64;
            (
                (kz as f64 - FIG7_EXACT.0).abs() / FIG7_EXACT.0,
                (at5 - FIG7_EXACT.1).abs(),
                list.len(),
            )
        })
        .collect()
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let runs = trials.unwrap_or(DEFAULT_RUNS);
    let mean = |adaptive_passes: bool| -> Vec<(f64, f64, f64)> {
        let mut acc = vec![(0.0, 0.0, 0.0); PASSES];
        for r in 0..runs {
            for (a, (e, e5, n)) in acc.iter_mut().zip(run_once(adaptive_passes, r)) {
                a.0 += e / runs as f64;
                a.1 += e5 / runs as f64;
                a.2 += n as f64 / runs as f64;
            }
        }
        acc
    };
    let (ad, un) = (mean(true), mean(false));
    let rows: Vec<Vec<String>> = (0..PASSES)
        .map(|p| {
            vec![
                (p + 1).to_string(),
                format!("{:.3e}", ad[p].0),
                format!("{:.3e}", ad[p].1),
                format!("{:.1}", ad[p].2),
                format!("{:.3e}", un[p].0),
                format!("{:.3e}", un[p].1),
                format!("{:.1}", un[p].2),
            ]
        })
        .collect();
    w.csv(
        "convergence.csv",
        &[
            "pass",
            "adaptive_rel_err_Kz",
            "adaptive_abs_err_K5",
            "adaptive_entries",
            "uniform_rel_err_Kz",
            "uniform_abs_err_K5",
            "uniform_entries",
        ],
        &rows,
    )?;
    let at = |p: usize| {
        format!(
            "| {} | {:.2e} | {:.2e} | {:.0} | {:.2e} | {:.2e} | {:.0} |",
            p,
            ad[p - 1].0,
            ad[p - 1].1,
            ad[p - 1].2,
            un[p - 1].0,
            un[p - 1].1,
            un[p - 1].2
        )
    };
    let table: Vec<String> = [1, 2, 4, 8, 16, 24, 32, 40]
        .iter()
        .map(|&p| at(p))
        .collect();
    Ok(format!(
        "Lerzer and Dachsbacher 2025 Fig. 7: convergence of the importance segments on an analytic importance with narrow peaks \
         (width 0.05, 0.3 and 0.01 on a ray of length 10; exact ∫k² = {:.3}, K(5) = {:.2}); N = {N} samples per pass, \
         d = 2L/N, mean over {runs} runs.\n\n\
         | passes | adaptive: rel. error K(z) | adaptive: error K(5) | entries | uniform: rel. error K(z) | uniform: error K(5) | entries |\n\
         |---|---|---|---|---|---|---|\n{}\n\n\
         The paper: the integral reaches float precision and K(5) becomes exact. Here the adaptive schedule brackets \
         every change point geometrically once a sample has landed in its peak; the thinnest peak (a thousandth of the \
         ray) is found by chance inside its segment, so the mean error falls in steps as runs find it.",
        FIG7_EXACT.0,
        FIG7_EXACT.1,
        table.join("\n")
    ))
}

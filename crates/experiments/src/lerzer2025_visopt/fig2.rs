//! Lerzer and Dachsbacher 2025 Fig. 2 / Eq. 5: AZD17's optimisation as printed (sums of g_j²
//! over the march samples) makes important regions vanish as the step
//! shrinks, since the sums grow with the sample count; with the paper's
//! Δx-normalised sums (≈ ∫ k²) the optimised extinction converges. Mean
//! μ'/μ over the samples of a camera ray through a procedural cloud whose
//! dense core has importance 0.9 (g ∈ [0, 0.9], as in the figure), steps
//! 0.01, 0.001, 0.0001 in the volume's [−1, 1]³ units.

use crate::harness::Writer;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

const SCENE: &str = include_str!("fig2.toml");

const STEPS: [f32; 3] = [0.01, 0.001, 0.0001];

/// Mean μ'/μ over the centre ray's samples, and over those with g > 0.
fn factors(form: &str, step: f32) -> Result<(f64, f64), String> {
    let extra = [
        format!("integrator.form=\"{form}\""),
        format!("integrator.step={step}"),
    ];
    let desc = parse_scene(SCENE, "visopt-fig2", &extra).map_err(|e| e.to_string())?;
    let s = Scene::build(desc, Path::new(".")).map_err(|e| e.to_string())?;
    let IntegratorKind::Ament(a) = &s.integrator else {
        return Err("not the ament integrator".into());
    };
    let f = a.factors(&s.world, 4, 4);
    let m = &s.world.media[0];
    let all = f.iter().map(|(_, v)| *v as f64).sum::<f64>() / f.len().max(1) as f64;
    let important: Vec<f64> = f
        .iter()
        .filter(|(p, _)| m.sigma_t_smooth(*p) >= 4.0)
        .map(|(_, v)| *v as f64)
        .collect();
    let imp = important.iter().sum::<f64>() / important.len().max(1) as f64;
    Ok((all, imp))
}

pub fn run(w: &mut Writer, _trials: Option<u64>) -> Result<String, String> {
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    for form in ["printed", "normalised"] {
        for step in STEPS {
            let (all, imp) = factors(form, step)?;
            rows.push(vec![
                form.to_string(),
                step.to_string(),
                format!("{all:.5}"),
                format!("{imp:.5}"),
            ]);
            lines.push(format!("| {form} | {step} | {all:.4} | {imp:.4} |"));
        }
    }
    w.csv(
        "factors.csv",
        &["form", "step", "mean_factor", "mean_factor_important"],
        &rows,
    )?;
    Ok(format!(
        "Lerzer and Dachsbacher 2025 Fig. 2 (Eq. 5): mean μ'/μ along the centre camera ray of a 64³ procedural cloud whose core \
         (σ_t ≥ 4) has importance 0.9, p, q, r, λ = 1, 70, 30, 1.\n\n\
         | form | step ([−1, 1]³ units) | mean μ'/μ | mean μ'/μ where important |\n|---|---|---|---|\n{}\n\n\
         As printed, each tenfold smaller step multiplies the sums in h by about ten and μ' collapses, the important \
         region included (the paper's figure: it vanishes); normalised by Δx the factors converge.",
        lines.join("\n")
    ))
}

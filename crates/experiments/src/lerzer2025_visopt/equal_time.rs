//! Lerzer and Dachsbacher 2025 Figs. 5 and 8 on the CPU: `visopt` against the ray-marched
//! AZD17 optimisation (normalised form) at equal time, and visopt's error
//! as its spp grow — RMSE and FLIP against a high-spp visopt reference of
//! the same optimised image, as the paper does (its references have 10,000
//! spp). Scene: the HEPTANE stand-in of `visopt-overhead` (128³ procedural
//! cloud, two point lights), 64², lobe off. AZD17's step is the largest of
//! 0.02 / 0.01 / 0.005 whose frame fits the budget; its image differs from
//! the reference by the ray-marched h as well as by discretisation.

use super::overhead::heptane_standin;
use crate::harness::protocol::render_at;
use crate::harness::Writer;
use fogbank_image::metrics::{flip, rmse, Image};
use fogbank_render::{render, Progress, RenderOptions, Scene};
use std::time::Duration;

pub const DEFAULT_REFERENCE_SPP: u64 = 1024;
const WIDTH: u32 = 64;

fn scene(extra: &[&str]) -> Result<Scene, String> {
    heptane_standin(WIDTH, extra)
}

fn image(rgb: Vec<[f32; 3]>) -> Image {
    Image::new(WIDTH as usize, WIDTH as usize, rgb)
}

/// (RMSE, FLIP) of `test` against `reference`.
fn errors(reference: &Image, test: &Image) -> Result<(f64, f64), String> {
    Ok((rmse(reference, test)?, flip(reference, test)?.mean))
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let ref_spp = trials.unwrap_or(DEFAULT_REFERENCE_SPP) as u32;
    let visopt = scene(&["integrator.type=\"visopt\""])?;
    visopt.integrator.prepare(&visopt.world);
    let reference = render_at(&visopt, ref_spp, 1000);
    let ref_img = image(reference.film.mean());
    let per_pass = reference.seconds / ref_spp as f64;
    let mut rows = Vec::new();
    let conv = error_against_spp(&visopt, &ref_img, &mut rows)?;
    let EqualTime {
        lines: eq,
        step,
        budget,
        azd17: (ae, af),
        visopt: (ve, vf),
    } = equal_time(&visopt, &ref_img, &mut rows)?;
    w.csv(
        "errors.csv",
        &["method", "spp", "seconds", "rmse", "flip"],
        &rows,
    )?;
    Ok(format!(
        "Lerzer and Dachsbacher 2025 Figs. 5 and 8 on the CPU (2 threads): the HEPTANE stand-in at {WIDTH}², errors against visopt at \
         {ref_spp} spp ({per_pass:.4} s per pass).\n\n\
         Fig. 8 — visopt's error against spp:\n\n| spp | s | RMSE | FLIP |\n|---|---|---|---|\n{}\n\n\
         Fig. 5 — equal time with AZD17 (normalised), the budget set by its finest step ({step}, {budget:.2} s):\n\n\
         | method | s | RMSE | FLIP |\n|---|---|---|---|\n{}\n\n\
         Ratios at equal time: RMSE AZD17/visopt = {:.2}, FLIP = {:.2}. The paper (GPU, HEPTANE, 14.7 s): ray \
         marching RMSE 0.0040 / FLIP 0.0127 against ours 0.0061 / 0.0106 — RM better in RMSE, ours in FLIP.",
        conv.join("\n"),
        eq.join("\n"),
        ae / ve,
        af / vf
    ))
}

/// One CSV row of `errors.csv`.
fn row(method: String, spp: String, seconds: f64, e: f64, f: f64) -> Vec<String> {
    vec![
        method,
        spp,
        format!("{seconds:.4}"),
        format!("{e:.6}"),
        format!("{f:.5}"),
    ]
}

/// Fig. 8: visopt's error at 1, 4, 16 and 64 spp; its rows join `rows`,
/// returns the Markdown lines.
fn error_against_spp(
    visopt: &Scene,
    ref_img: &Image,
    rows: &mut Vec<Vec<String>>,
) -> Result<Vec<String>, String> {
    let mut conv = Vec::new();
    for spp in [1u32, 4, 16, 64] {
        let r = render_at(visopt, spp, 7);
        let (e, f) = errors(ref_img, &image(r.film.mean()))?;
        rows.push(row("visopt".into(), spp.to_string(), r.seconds, e, f));
        conv.push(format!("| {spp} | {:.3} | {e:.5} | {f:.4} |", r.seconds));
    }
    Ok(conv)
}

/// What [`equal_time`] found.
struct EqualTime {
    /// The Markdown table's lines.
    lines: Vec<String>,
    /// AZD17's finest step and the seconds of its frame: the budget.
    step: f32,
    budget: f64,
    /// (RMSE, FLIP) of AZD17 at that step and of visopt in that time.
    azd17: (f64, f64),
    visopt: (f64, f64),
}

/// Fig. 5: one AZD17 frame at each step, then visopt for as long as the
/// finest took; the rows join `rows`.
fn equal_time(
    visopt: &Scene,
    ref_img: &Image,
    rows: &mut Vec<Vec<String>>,
) -> Result<EqualTime, String> {
    let mut eq = Vec::new();
    let mut chosen = None;
    for step in [0.02f32, 0.01, 0.005] {
        let a = scene(&[
            "integrator.type=\"ament\"",
            &format!("integrator.step={step}"),
        ])?;
        let r = render_at(&a, 1, 1);
        let (e, f) = errors(ref_img, &image(r.film.mean()))?;
        rows.push(row(
            format!("ament step {step}"),
            "1".into(),
            r.seconds,
            e,
            f,
        ));
        eq.push(format!(
            "| AZD17, step {step} (one frame) | {:.3} | {e:.5} | {f:.4} |",
            r.seconds
        ));
        chosen = Some((step, r.seconds, e, f));
    }
    let (step, budget, ae, af) = chosen.ok_or("no AZD17 run")?;
    let r = render(
        visopt,
        &RenderOptions {
            spp: 1 << 20,
            seed: 11,
            time_budget: Some(Duration::from_secs_f64(budget)),
        },
        &Progress::default(),
    );
    let spp = r.film.min_spp();
    let (ve, vf) = errors(ref_img, &image(r.film.mean()))?;
    rows.push(row(
        "visopt equal time".into(),
        spp.to_string(),
        r.seconds,
        ve,
        vf,
    ));
    eq.push(format!(
        "| visopt in the same time ({spp} spp) | {:.3} | {ve:.5} | {vf:.4} |",
        r.seconds
    ));
    Ok(EqualTime {
        lines: eq,
        step,
        budget,
        azd17: (ae, af),
        visopt: (ve, vf),
    })
}

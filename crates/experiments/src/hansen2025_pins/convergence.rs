//! Hansen 2025 Figs. 4.12–4.24: error over time of the ray-marching baseline,
//! PinMS (both at the scene's middle step) and fogbank's unbiased `volpath`
//! (delta tracking, ratio-tracking NEE), each accumulating 1-spp frames for
//! the same render-time budget (taking turns frame by frame, so the noisy
//! machine's drift hits all three alike), on four of Fig. 4.11's scenes (their
//! stand-ins, `runtime::CASES`). MSE of the running mean against an
//! unbiased reference (its variance subtracted) over time, log–log plots,
//! and HDR-FLIP of the running means at the thesis's two budgets (1 s and
//! 10 s; here on the CPU at 64×48, so the budgets buy far fewer samples per
//! pixel than the thesis's GPU at 512²) with the images.

use super::runtime::{scene, Case, CASES};
use crate::harness::protocol::{build, race, Reference};
use crate::harness::Writer;
use fogbank_eval::plot::{palette, Corner, Figure, LinePlot, Series};
use fogbank_image::metrics::flip::flip;
use fogbank_image::Image;

/// The thesis's two equal-time budgets, seconds.
pub const BUDGETS: [f64; 2] = [1.0, 10.0];
/// Fig. 4.11's rows used here: Teapot, Cloud, Many Clouds, Cube.
const ROWS: [usize; 4] = [0, 2, 3, 4];
const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

/// (label, overrides) of the three methods at ray-marching step `step`.
pub fn methods(step: f32) -> [(&'static str, Vec<String>); 3] {
    let step = format!("integrator.march_step={step}");
    [
        (
            "ray marching",
            vec![step.clone(), "integrator.tracking=ray_marching".into()],
        ),
        ("PinMS", vec![step, "integrator.pins=ms".into()]),
        ("unbiased volpath", vec![]),
    ]
}

fn image(rgb: &[[f32; 3]]) -> Image {
    Image {
        width: WIDTH as usize,
        height: HEIGHT as usize,
        rgb: rgb.to_vec(),
        variance: None,
        is_srgb8: false,
    }
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let reference_spp = trials.unwrap_or(512).min(1 << 16) as u32;
    let budget = BUDGETS[1];
    let mut fig = Figure::new(2).title("Hansen 2025 Figs. 4.12-4.24: MSE over render time (CPU)");
    let (mut rows, mut lines) = (Vec::new(), Vec::new());
    for &row in &ROWS {
        let (line, plot) = measure_case(w, &CASES[row], reference_spp, &mut rows)?;
        lines.push(line);
        fig = fig.with(plot);
    }
    w.figure("mse_over_time", &fig)?;
    w.csv(
        "convergence.csv",
        &[
            "scene",
            "method",
            "step",
            "spp_in_budget",
            "mse_1s",
            "mse_10s",
            "flip_1s",
            "flip_10s",
        ],
        &rows,
    )?;
    Ok(format!(
        "Hansen 2025 error over time on fogbank's CPU ({} threads), {WIDTH}×{HEIGHT}, 8 bounces, sky probe: 1-spp frames \
         accumulated for {budget} s of render time per method; MSE of the running mean against unbiased `volpath` at \
         {reference_spp} spp (its variance subtracted) and HDR-FLIP at 1 s → 10 s (lower is better). Plot: \
         mse_over_time.png; images: <scene>_<method>_<budget>s.png.\n\n| scene | at 1 s → 10 s |\n|---|---|\n{}\n",
        rayon::current_num_threads(),
        lines.join("\n")
    ))
}

/// One scene: its reference (`<scene>_reference.png`), then the three
/// methods raced for the larger budget, their running means at both
/// budgets (`<scene>_<method>_<budget>s.png`); the CSV rows join `rows`,
/// returns the Markdown line and the MSE-over-time panel.
fn measure_case(
    w: &mut Writer,
    case: &Case,
    reference_spp: u32,
    rows: &mut Vec<Vec<String>>,
) -> Result<(String, LinePlot), String> {
    let text = scene(case, WIDTH, HEIGHT)?;
    let reference = Reference::render(&build(&text, &[])?, reference_spp, 0x0412);
    let stem = case.name.to_lowercase().replace(' ', "_");
    w.png(
        &format!("{stem}_reference.png"),
        WIDTH,
        HEIGHT,
        &reference.rgb,
        0.0,
    )?;
    let mut plot = LinePlot::new(case.name, "seconds", "MSE")
        .log_x()
        .log_y()
        .legend(Corner::UpperRight);
    let mut cells = Vec::new();
    let methods = methods(case.steps[1]);
    let sets: Vec<Vec<String>> = methods.iter().map(|(_, set)| set.clone()).collect();
    let runs = race(&text, &sets, &reference, BUDGETS[1], &BUDGETS, 0x0412)?;
    for (i, ((frames, shots), (label, _))) in runs.into_iter().zip(&methods).enumerate() {
        let spp = frames.curve.len();
        let mse_at = |t: f64| {
            frames
                .curve
                .iter()
                .find(|p| p.0 >= t)
                .or(frames.curve.last())
                .map_or(f64::NAN, |p| p.1)
        };
        let mut flips = Vec::new();
        for (b, shot) in BUDGETS.iter().zip(&shots) {
            let f = flip(&image(&reference.rgb), &image(shot))?;
            let name = format!("{stem}_{}_{b}s.png", label.replace(' ', "_"));
            w.png(&name, WIDTH, HEIGHT, shot, 0.0)?;
            flips.push(f.mean);
        }
        rows.push(vec![
            case.name.to_string(),
            label.to_string(),
            case.steps[1].to_string(),
            spp.to_string(),
            format!("{:.4e}", mse_at(BUDGETS[0])),
            format!("{:.4e}", mse_at(BUDGETS[1])),
            format!("{:.4}", flips[0]),
            format!("{:.4}", flips[1]),
        ]);
        cells.push(format!(
            "{label}: {spp} spp, MSE {:.1e} → {:.1e}, FLIP {:.3} → {:.3}",
            mse_at(BUDGETS[0]),
            mse_at(BUDGETS[1]),
            flips[0],
            flips[1]
        ));
        plot = plot.with(Series::line(*label, frames.log_curve(), palette(i)));
    }
    let line = format!(
        "| {} (step {}) | {} |",
        case.name,
        case.steps[1],
        cells.join(" · ")
    );
    Ok((line, plot))
}

#[cfg(test)]
mod convergence_test {
    use super::*;
    use crate::harness::protocol::frames_within;
    use fogbank_math::testdata::skip_unless_required;

    /// Every method of every row builds, and a budgeted run keeps one
    /// running-mean image per budget, its curve's times rising to the
    /// budget.
    #[test]
    fn methods_build_and_budgets_are_kept() {
        for &row in &ROWS {
            let case = &CASES[row];
            let Ok(text) = scene(case, 8, 6).map_err(|e| skip_unless_required::<()>(&e)) else {
                continue;
            };
            for (label, set) in methods(case.steps[1]) {
                let mut set = set.clone();
                set.push("integrator.pin_grid.positions=2".into());
                build(&text, &set).unwrap_or_else(|e| panic!("{} {label}: {e}", case.name));
            }
        }
        let text = scene(&CASES[2], 8, 6).unwrap();
        let s = build(&text, &[]).unwrap();
        let reference = Reference::render(&s, 4, 1);
        let (frames, shots) = frames_within(&s, &reference, 1, 0.05, &[0.0, 0.05], 3);
        assert_eq!(shots.len(), 2);
        assert!(frames.curve.last().unwrap().0 >= 0.05);
        assert!(frames.curve.windows(2).all(|w| w[1].0 >= w[0].0));
        assert_eq!(shots[0].len(), 48);
    }
}

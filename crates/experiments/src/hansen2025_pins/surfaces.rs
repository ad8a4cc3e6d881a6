//! Hansen 2025 Figs. 4.12–4.13 with surfaces: the Teapot
//! stand-in (`runtime::CASES[0]`, sphere.vdb as fog, σ_t 40) on a
//! diffuse ground, lit from the left by an emitting rectangle (the thesis's
//! area light from the left) and a dim sky; 8 bounces. Ray marching
//! (the baseline), PinMS (ray marching for the primary ray and first-vertex
//! NEE, pins from vertex 2 on — at surface vertices too) and the unbiased
//! `volpath` each accumulate 1-spp frames for the same render time at the
//! thesis's step 0.03, taking turns frame by frame; MSE of the running mean
//! against an unbiased reference (its variance subtracted) over the image
//! and over the ground's shadow — ground pixels whose path to the light
//! crosses the medium's box: surface shadows through a pinned medium.
//! Then the bias ordering at each of the thesis's three steps (equal-time
//! MSE of ray marching and PinMS): the thesis finds pins more biased at
//! every step and contrast lost at the hard edges.

use super::runtime::CASES;
use crate::harness::protocol::{build, race, Reference};
use crate::harness::Writer;
use fogbank_eval::plot::{palette, Corner, Figure, LinePlot, Series};
use fogbank_math::{Ray, Vec3};
use fogbank_render::Scene;

pub const WIDTH: u32 = 96;
pub const HEIGHT: u32 = 72;
/// The area light's centre (to the left of the teapot stand-in).
const LIGHT: [f32; 3] = [-1.6, 0.5, 0.2];

/// The scene: the Teapot stand-in, a ground, the area light, a dim sky.
pub fn scene() -> Result<String, String> {
    Ok(format!(
        "[camera]\nfrom = [0.0, 0.5, 2.4]\nto = [0.0, -0.1, 0.0]\nfov = 40.0\nwidth = {WIDTH}\nheight = {HEIGHT}\n\
         {}[[shapes]]\ntype = \"rectangle\"\n\
         to_world = {{ translate = [0.0, -0.45, 0.0], rotate = [1.0, 0.0, 0.0, -90.0], scale = 2.0 }}\n\
         bsdf = {{ type = \"diffuse\", reflectance = 0.6 }}\n\
         [[shapes]]\ntype = \"rectangle\"\n\
         to_world = {{ translate = [{}, {}, {}], rotate = [0.0, 1.0, 0.0, 90.0], scale = 0.35 }}\n\
         emitter = {{ radiance = [12.0, 11.0, 10.0] }}\n\
         [[lights]]\ntype = \"constant\"\nradiance = [0.03, 0.035, 0.045]\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 8\n[render]\npixel_jitter = false\n",
        CASES[0].media()?,
        LIGHT[0],
        LIGHT[1],
        LIGHT[2]
    ))
}

/// Pixels whose camera ray first meets the ground (shape 0) at a point
/// whose segment to the light's centre crosses the medium's box.
pub fn shadow_region(s: &Scene) -> Vec<bool> {
    let w = &s.world;
    let (Some(surfaces), Some(m)) = (&w.surfaces, w.media.first()) else {
        return Vec::new();
    };
    let light = Vec3::from(LIGHT);
    let mut region = Vec::with_capacity((WIDTH * HEIGHT) as usize);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let ray = w.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
            let shadowed = surfaces
                .intersect(&ray, f32::INFINITY)
                .filter(|h| h.shape == 0)
                .is_some_and(|h| {
                    let to = light - h.p;
                    let dist = to.length();
                    m.medium
                        .to_index(&Ray::new(h.p, to / dist), 0.0, dist)
                        .is_some()
                });
            region.push(shadowed);
        }
    }
    region
}

/// MSE over the pixels of `region`, the reference's variance there
/// subtracted.
pub fn region_mse(img: &[[f32; 3]], r: &Reference, region: &[bool]) -> f64 {
    let (mut sum, mut floor, mut n) = (0.0f64, 0.0f64, 0usize);
    for (i, _) in region.iter().enumerate().filter(|(_, &inside)| inside) {
        for ((x, y), v) in img[i].iter().zip(&r.rgb[i]).zip(&r.var[i]) {
            let d = (x - y) as f64;
            sum += d * d;
            floor += *v as f64;
        }
        n += 3;
    }
    if n == 0 {
        return f64::NAN;
    }
    ((sum - floor) / n as f64).max(0.0)
}

/// Seconds of frames per method in the error-over-time race (Fig. 4.13)
/// and per step in the bias race (Fig. 4.12).
const BUDGET: f64 = 10.0;
const SHORT: f64 = 3.0;

fn methods(step: f32) -> [(&'static str, Vec<String>); 3] {
    super::convergence::methods(step)
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let reference_spp = trials.unwrap_or(1024).min(1 << 16) as u32;
    let text = scene()?;
    let base = build(&text, &[])?;
    let region = shadow_region(&base);
    let shadow_pixels = region.iter().filter(|&&b| b).count();
    let reference = Reference::render(&base, reference_spp, 0x0413);
    w.png("reference.png", WIDTH, HEIGHT, &reference.rgb, 0.0)?;
    let mask: Vec<[f32; 3]> = region
        .iter()
        .zip(&reference.rgb)
        .map(|(&b, p)| if b { [1.0, 0.2, 0.2] } else { *p })
        .collect();
    w.png("shadow_region.png", WIDTH, HEIGHT, &mask, 0.0)?;

    let step = CASES[0].steps[1];
    let mut rows = Vec::new();
    let lines = over_time(w, &text, &reference, &region, &mut rows)?;
    let steps = bias_per_step(&text, &reference, &region, &mut rows)?;
    w.csv(
        "pins_surfaces.csv",
        &["method", "step", "spp_in_budget", "mse", "shadow_mse"],
        &rows,
    )?;
    Ok(format!(
        "Hansen 2025 Figs. 4.12–4.13 with surfaces on fogbank's CPU ({} threads), {WIDTH}×{HEIGHT}, 8 bounces: the Teapot \
         stand-in (sphere.vdb fog, σ_t 40) on a diffuse ground, an emitting rectangle to the left, a dim sky. \
         Reference: unbiased `volpath` at {reference_spp} spp (its variance subtracted from every MSE). \
         Shadow region: {shadow_pixels} ground pixels whose segment to the light crosses the medium's box \
         (`shadow_region.png`).\n\n\
         Error after {budget} s of 1-spp frames at the thesis's step {step} (`mse_over_time.png`, images \
         `<method>_{budget}s.png`):\n\n| method | spp in budget | MSE | shadow-region MSE |\n|---|---|---|---|\n{}\n\n\
         Bias at each of the thesis's steps ({short} s each):\n\n\
         | step | RM MSE | PinMS MSE | PinMS/RM | RM shadow MSE | PinMS shadow MSE |\n|---|---|---|---|---|---|\n{}\n",
        rayon::current_num_threads(),
        lines.join("\n"),
        steps.join("\n"),
        budget = BUDGET,
        short = SHORT,
    ))
}

/// Fig. 4.13: error over time at the thesis's step, [`BUDGET`] seconds of
/// 1-spp frames per method taking turns (`mse_over_time`, the final images
/// `<method>_10s.png`); the rows join `rows`, returns the Markdown lines.
fn over_time(
    w: &mut Writer,
    text: &str,
    reference: &Reference,
    region: &[bool],
    rows: &mut Vec<Vec<String>>,
) -> Result<Vec<String>, String> {
    let step = CASES[0].steps[1];
    let budget = BUDGET;
    let methods = methods(step);
    let sets: Vec<Vec<String>> = methods.iter().map(|(_, set)| set.clone()).collect();
    let runs = race(text, &sets, reference, budget, &[budget], 0x0412)?;
    let mut plot = LinePlot::new(
        "Teapot stand-in, area light from the left",
        "seconds",
        "MSE",
    )
    .log_x()
    .log_y()
    .legend(Corner::UpperRight);
    let mut lines = Vec::new();
    for (i, ((frames, shots), (label, _))) in runs.into_iter().zip(&methods).enumerate() {
        let last = shots.last().cloned().unwrap_or_default();
        let stem = label.replace(' ', "_");
        w.png(&format!("{stem}_{budget}s.png"), WIDTH, HEIGHT, &last, 0.0)?;
        let (mse, shadow) = (reference.mse(&last), region_mse(&last, reference, region));
        rows.push(vec![
            label.to_string(),
            step.to_string(),
            frames.curve.len().to_string(),
            format!("{mse:.4e}"),
            format!("{shadow:.4e}"),
        ]);
        lines.push(format!(
            "| {label} | {} | {mse:.2e} | {shadow:.2e} |",
            frames.curve.len()
        ));
        plot = plot.with(Series::line(*label, frames.log_curve(), palette(i)));
    }
    w.figure(
        "mse_over_time",
        &Figure::new(1)
            .title("Hansen 2025 Fig. 4.13 with surfaces: MSE over render time (CPU)")
            .with(plot),
    )?;
    Ok(lines)
}

/// Fig. 4.12's bias at each step: [`SHORT`] seconds each, ray marching vs
/// PinMS at equal time; the rows join `rows`, returns the Markdown lines.
fn bias_per_step(
    text: &str,
    reference: &Reference,
    region: &[bool],
    rows: &mut Vec<Vec<String>>,
) -> Result<Vec<String>, String> {
    let short = SHORT;
    let mut steps = Vec::new();
    for s in CASES[0].steps {
        let runs = race(text, &methods_at(s), reference, short, &[short], 0x0512)?;
        let mut cells = Vec::new();
        for (_, shots) in runs {
            let last = shots.last().cloned().unwrap_or_default();
            cells.push((reference.mse(&last), region_mse(&last, reference, region)));
        }
        rows.push(vec![
            "ray marching vs PinMS".into(),
            s.to_string(),
            String::new(),
            format!("{:.4e} vs {:.4e}", cells[0].0, cells[1].0),
            format!("{:.4e} vs {:.4e}", cells[0].1, cells[1].1),
        ]);
        steps.push(format!(
            "| {s} | {:.2e} | {:.2e} | {:.2}× | {:.2e} | {:.2e} |",
            cells[0].0,
            cells[1].0,
            cells[1].0 / cells[0].0,
            cells[0].1,
            cells[1].1
        ));
    }
    Ok(steps)
}

/// Ray marching and PinMS at `step`.
fn methods_at(step: f32) -> [Vec<String>; 2] {
    let [rm, pins, _] = methods(step);
    [rm.1, pins.1]
}

#[cfg(test)]
mod pins_surfaces_test {
    use super::*;

    /// Every method builds on the scene, and the shadow region is ground
    /// that the medium's box hides from the light: some pixels, not all.
    #[test]
    fn the_scene_builds_and_its_shadow_region_is_ground_behind_the_medium() {
        let text = scene().unwrap();
        for step in CASES[0].steps {
            for set in methods_at(step) {
                build(&text, &set).unwrap();
            }
        }
        let s = build(&text, &[]).unwrap();
        let region = shadow_region(&s);
        let n = region.iter().filter(|&&b| b).count();
        assert!(n > 100 && n < region.len() / 2, "{n} of {}", region.len());
        // The top row sees the sky and the medium, never the ground.
        assert!(!region[..WIDTH as usize].iter().any(|&b| b));
    }
}

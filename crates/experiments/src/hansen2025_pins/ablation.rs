//! Hansen 2025's ablations (Figs. 4.2–4.5, 4.7, 4.8) on one scene: a 64³
//! procedural cloud, albedo 1, isotropic, 8 bounces, sky probe plus a sun
//! (the thesis's directional-light case of Fig. 4.3), pixel centres. Each
//! row renders `volpath` with one pin setting at equal spp and reports the
//! MSE against an unbiased `volpath` reference (its variance subtracted),
//! the relative bias of the image mean, and the time per sample; one
//! parameter changes per study, the rest at the thesis's evaluation
//! defaults (PinMS, k = 5, jitter 1, 16 φ × 4 θ, grid 0.1× the texture).
//! The stream (Figs. 4.1, 4.6) is not in renders yet.

use crate::harness::protocol::{build, independent_frames, Reference};
use crate::harness::Writer;

pub const DEFAULT_SPP: u64 = 64;
const STEP: &str = "integrator.march_step=0.03";

pub const SCENE: &str = "[camera]\nfrom = [0.0, 0.1, 2.0]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = 64\nheight = 48\n\
    [[media]]\ndensity = { procedural = \"cloud\", resolution = 64, seed = 7 }\n\
    sigma_t_scale = 20.0\nalbedo = [1.0, 1.0, 1.0]\n\
    [[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n\
    [[lights]]\ntype = \"directional\"\ndirection = [-0.5, -0.7, -0.4]\nirradiance = [2.0, 1.9, 1.7]\n\
    [integrator]\ntype = \"volpath\"\nmax_depth = 8\n[render]\npixel_jitter = false\n";

/// (figure, setting label, scene overrides).
pub fn studies() -> Vec<(&'static str, String, Vec<String>)> {
    let ms = |extra: &[&str]| -> Vec<String> {
        let mut v = vec!["integrator.pins=ms".to_string(), STEP.to_string()];
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let mut out = vec![(
        "baseline",
        "ray marching (step 0.03)".to_string(),
        vec![
            "integrator.tracking=ray_marching".to_string(),
            STEP.to_string(),
        ],
    )];
    for k in [1, 2, 3, 5, 8] {
        out.push((
            "4.2",
            format!("mask iterations k = {k}"),
            ms(&[&format!("integrator.pin_grid.mask_iterations={k}")]),
        ));
    }
    for mode in ["all", "secondary", "ms"] {
        let set = format!("integrator.pins={mode}");
        out.push(("4.3", format!("pins = {mode}"), vec![set, STEP.to_string()]));
    }
    for j in ["0", "0.5", "1"] {
        out.push((
            "4.4",
            format!("jitter {j}"),
            ms(&[&format!("integrator.pin_grid.jitter={j}")]),
        ));
    }
    out.push((
        "4.5",
        "unquantised pins (along each ray)".into(),
        ms(&["integrator.pin_grid.unquantised=true"]),
    ));
    out.push(("4.5", "grid pins".into(), ms(&[])));
    // Fig. 4.7: at about 1× the texture (0.52 MB for this 64³ cloud):
    // directional resolution (P = 4, 16 × 64 directions) against
    // positional (P = 10, 16 × 4).
    out.push((
        "4.7",
        "all rays, directions 64×16, P = 4".into(),
        vec![
            "integrator.pins=all".into(),
            STEP.into(),
            "integrator.pin_grid.positions=4".into(),
            "integrator.pin_grid.phi=64".into(),
            "integrator.pin_grid.theta=16".into(),
        ],
    ));
    out.push((
        "4.7",
        "all rays, directions 16×4, P = 10".into(),
        vec![
            "integrator.pins=all".into(),
            STEP.into(),
            "integrator.pin_grid.positions=10".into(),
        ],
    ));
    for r in ["0.1", "1", "10"] {
        out.push((
            "4.8",
            format!("grid {r}× the texture"),
            ms(&[&format!("integrator.pin_grid.memory_ratio={r}")]),
        ));
    }
    out
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let spp = trials.unwrap_or(DEFAULT_SPP).clamp(1, 1 << 14) as u32;
    let reference = Reference::render(&build(SCENE, &[])?, 8 * spp, 0x0442);
    let mean = |img: &[[f32; 3]]| img.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum::<f64>();
    let ref_mean = mean(&reference.rgb);
    w.png("reference.png", 64, 48, &reference.rgb, 0.0)?;
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    for (i, (fig, label, set)) in studies().into_iter().enumerate() {
        let scene = build(SCENE, &set).map_err(|e| format!("{label}: {e}"))?;
        let f = independent_frames(&scene, &reference, spp, 1, 0x1000 + i as u32);
        let bias = mean(&f.last) / ref_mean - 1.0;
        // Images of the pin-usage and representation studies (Figs. 4.3, 4.5).
        if fig == "baseline" || fig == "4.3" || fig == "4.5" {
            w.png(&format!("row{i:02}.png"), 64, 48, &f.last, 0.0)?;
        }
        let ms = f.ms / spp as f64;
        rows.push(vec![
            fig.to_string(),
            label.clone(),
            format!("{:.4e}", f.mse),
            format!("{bias:+.4}"),
            format!("{ms:.3}"),
        ]);
        lines.push(format!(
            "| {fig} | {label} | {:.3e} | {:+.2} % | {ms:.2} |",
            f.mse,
            100.0 * bias
        ));
    }
    w.csv(
        "ablation.csv",
        &["figure", "setting", "mse", "mean_bias", "ms_per_spp"],
        &rows,
    )?;
    Ok(format!(
        "Hansen 2025 ablations on fogbank's CPU: 64×48, 64³ cloud, albedo 1, 8 bounces, sky probe + sun; {spp} spp per row \
         against unbiased `volpath` at {} spp; MSE (reference variance subtracted; includes each row's own noise), \
         relative bias of the image mean, time per sample (one run, noisy ±20 %).\n\n\
         | fig. | setting | MSE | mean bias | ms/spp |\n|---|---|---|---|---|\n{}\n\n\
         Images: `reference.png` and `rowNN.png` (row NN of `ablation.csv`, from 0) for the baseline and Figs. 4.3, 4.5.\n",
        8 * spp,
        lines.join("\n")
    ))
}

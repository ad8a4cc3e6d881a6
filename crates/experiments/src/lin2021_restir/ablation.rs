//! Lin et al. 2021's ablations (Figs. 4, 7, 10, 11, 12, 14, 15, 19, 21) on one
//! static scene with the protocol of `harness::protocol`: the procedural cloud
//! under the sky probe, K = 3, 128×96, ReSTIR frames after a warm-up against
//! an offline `volpath` reference. Each row changes one parameter of the
//! default configuration and reports the frame time, its split into the
//! passes of §5 (spatial radius 2 px by default, the smallest that reaches
//! distinct neighbours; see `equal_time::RADIUS`), per-frame colour and monochrome (luminance) MSE, and the
//! lag-1 autocorrelation of the error image (Fig. 15's correlation measure).
//! Figs. 19 and 21 change the scene (density ×0.2 and ×3; phase g = 0 and
//! 0.8) and compare at equal time with the baseline and the null-scattering
//! tracer (`volpath` with NEE/phase MIS and residual ratio tracking).
//! The supplementary study compares direction and vertex reuse. The
//! dynamic-scene figures (8, 9, 13) are in `dynamic` and `bias`.

use super::race::{equal_time_race, restir_frames, Rival};
use crate::harness::protocol::{build, set, spp, Frames, Reference};
use crate::harness::Writer;

const WARM_UP: u32 = 8;
const FRAMES: u32 = 16;

/// (figure, configuration, overrides): each row changes one parameter of
/// the default configuration.
const CONFIGS: &[(&str, &str, &[&str])] = &[
    ("default", "spatiotemporal, Talbot, radius 2 px", &[]),
    ("4", "no reuse", &["integrator.reuse=none"]),
    ("4", "spatial only", &["integrator.reuse=spatial"]),
    ("4", "temporal only", &["integrator.reuse=temporal"]),
    (
        "7",
        "stochastic MIS (Eq. 10)",
        &["integrator.mis=stochastic"],
    ),
    ("suppl.", "vertex reuse", &["integrator.shift=vertex"]),
    (
        "beyond",
        "pairwise MIS (2N target evaluations)",
        &["integrator.mis=pairwise"],
    ),
    ("10", "reuse T̃ full resolution", &["integrator.reuse_mip=0"]),
    ("10", "reuse T̃ mip 3", &["integrator.reuse_mip=3"]),
    ("10", "reuse T̃ mip 1, BC4", &["integrator.reuse_bc4=true"]),
    (
        "11",
        "candidate NEE T̃ full resolution",
        &["integrator.nee_mip=0"],
    ),
    (
        "11",
        "no candidate NEE T̃",
        &["integrator.nee_transmittance=false"],
    ),
    (
        "12",
        "candidates exact trilinear, full res",
        &["integrator.primary_mip=0", "integrator.indirect_mip=0"],
    ),
    (
        "12",
        "candidates mip 3",
        &["integrator.primary_mip=3", "integrator.indirect_mip=3"],
    ),
    ("14", "Q = 1", &["integrator.temporal_cap=1"]),
    ("14", "Q = 20", &["integrator.temporal_cap=20"]),
    (
        "15",
        "radius 10 px (the paper's, in pixels)",
        &["integrator.radius=10"],
    ),
    ("15", "radius 5 px", &["integrator.radius=5"]),
    ("15", "radius 20 px", &["integrator.radius=20"]),
    ("15", "radius 40 px", &["integrator.radius=40"]),
];

fn scene(scale: f32, g: f32) -> String {
    format!(
        "[camera]\nfrom = [0.0, 0.1, 2.0]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = 128\nheight = 96\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 128, seed = 7 }}\n\
         sigma_t_scale = {scale}\nalbedo = [0.95, 0.95, 0.95]\nphase = {{ type = \"hg\", g = {g} }}\n\
         [[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n\
         [integrator]\ntype = \"restir\"\nmax_depth = 3\nradius = 2.0\n[render]\npixel_jitter = false\n"
    )
}

/// Lag-1 (horizontal and vertical) autocorrelation of the luminance error.
fn error_autocorrelation(img: &[[f32; 3]], reference: &Reference, width: usize) -> f64 {
    let e: Vec<f64> = img
        .iter()
        .zip(&reference.rgb)
        .map(|(a, r)| (0..3).map(|c| a[c] as f64 - r[c] as f64).sum::<f64>() / 3.0)
        .collect();
    let mean = e.iter().sum::<f64>() / e.len() as f64;
    let var = e.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / e.len() as f64;
    let (mut sum, mut n) = (0.0, 0usize);
    for i in 0..e.len() {
        if (i + 1) % width != 0 {
            sum += (e[i] - mean) * (e[i + 1] - mean);
            n += 1;
        }
        if i + width < e.len() {
            sum += (e[i] - mean) * (e[i + width] - mean);
            n += 1;
        }
    }
    if var > 0.0 {
        sum / n as f64 / var
    } else {
        0.0
    }
}

fn row(figure: &str, config: &str, f: &Frames, reference: &Reference) -> Vec<String> {
    vec![
        figure.to_string(),
        config.to_string(),
        format!("{:.1}", f.ms),
        format!("{:.1}", 1e3 * f.passes.candidates),
        format!("{:.1}", 1e3 * f.passes.temporal),
        format!("{:.1}", 1e3 * f.passes.spatial),
        format!("{:.1}", 1e3 * f.passes.shading),
        format!("{:.4e}", f.mse),
        format!("{:.4e}", f.mono_mse),
        format!("{:.3}", error_autocorrelation(&f.last, reference, 128)),
    ]
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let reference_spp = spp(trials, 256);
    let threads = rayon::current_num_threads();
    let mut rows = Vec::new();
    let base = scene(40.0, 0.5);
    let reference = Reference::render(
        &build(&base, &set(&["integrator.type=volpath"]))?,
        reference_spp,
        0x5EED_0004,
    );
    for (fig, label, overrides) in CONFIGS {
        let scene = build(&base, &set(overrides))?;
        let f = restir_frames(&scene, &reference, WARM_UP, FRAMES, 0x5EED_0005);
        rows.push(row(fig, label, &f, &reference));
    }
    let equal_time = equal_time_rows(&mut rows, reference_spp)?;
    let header = [
        "figure",
        "configuration",
        "ms_per_frame",
        "candidates_ms",
        "temporal_ms",
        "spatial_ms",
        "shading_ms",
        "mse",
        "mono_mse",
        "error_autocorrelation_last_frame",
    ];
    w.csv("ablation.csv", &header, &rows)?;
    let table: Vec<String> = rows
        .iter()
        .map(|r| format!("| {} |", r.join(" | ")))
        .collect();
    Ok(format!(
        "Lin et al. 2021 ablations on fogbank's CPU backend ({threads} threads): procedural cloud under the sky probe, \
         K = 3, 128×96, spatial radius 2 px unless stated, {WARM_UP} warm-up + {FRAMES} measured frames, reference `volpath` at {reference_spp} spp \
         (its variance subtracted). Times are wall-clock per frame and per pass (ms).\n\n\
         | fig. | configuration | ms/frame | candidates | temporal | spatial | shading | MSE | mono MSE | error autocorrelation (last frame) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n{}\n\n\
         Equal time against the paper's baseline and the null-scattering tracer (frames timed in turn with ReSTIR's, their MSE at the matched spp scaled to ReSTIR's frame time):\n\n\
         | fig. | scene | ReSTIR ms/frame | ReSTIR MSE | baseline MSE (ratio) | null-scattering MSE (ratio) |\n|---|---|---|---|---|---|\n{}\n",
        table.join("\n"),
        equal_time.join("\n")
    ))
}

/// Fig. 19 (density) and Fig. 21 (phase): new scenes, each with its own
/// reference, ReSTIR against the baseline (and the null-scattering tracer)
/// at equal time (the 1-spp MSE scaled to ReSTIR's frame time). ReSTIR's
/// rows join `rows`; returns the Markdown lines of the equal-time table.
fn equal_time_rows(rows: &mut Vec<Vec<String>>, reference_spp: u32) -> Result<Vec<String>, String> {
    let mut equal_time = Vec::new();
    for (fig, label, scale, g) in [
        ("19", "density ×0.2", 8.0, 0.5),
        ("19", "density ×1", 40.0, 0.5),
        ("19", "density ×3", 120.0, 0.5),
        ("21", "g = 0", 40.0, 0.0),
        ("21", "g = 0.8", 40.0, 0.8),
    ] {
        let text = scene(scale, g);
        let reference = Reference::render(
            &build(&text, &set(&["integrator.type=volpath"]))?,
            reference_spp,
            0x5EED_0006,
        );
        let rival = |preset: &str| {
            build(
                &text,
                &set(&[
                    "integrator.type=volpath",
                    "integrator.max_depth=3",
                    preset,
                    "media.0.supervoxel=8",
                ]),
            )
        };
        let baseline_scene = rival("integrator.preset=restir_baseline")?;
        let null_scene = rival("integrator.preset=baseline")?;
        let (f, rivals) = equal_time_race(
            &build(&text, &[])?,
            &[&baseline_scene, &null_scene],
            &reference,
            WARM_UP,
            FRAMES,
            0x5EED_0007,
            3000,
        );
        rows.push(row(fig, label, &f, &reference));
        let at_equal_time = |r: &Rival| r.frames.mse * r.frames.ms / f.ms;
        let (baseline, null) = (at_equal_time(&rivals[0]), at_equal_time(&rivals[1]));
        equal_time.push(format!(
            "| {fig} | {label} | {:.1} | {:.3e} | {:.3e} ({:.2}×) | {:.3e} ({:.2}×) |",
            f.ms,
            f.mse,
            baseline,
            baseline / f.mse,
            null,
            null / f.mse
        ));
    }
    Ok(equal_time)
}

//! Lerzer and Dachsbacher 2025 Fig. 5 (right) and Table 3 on the CPU: what the optimisation
//! costs. On a HEPTANE stand-in (procedural cloud 128³ in [−1, 1]³, two
//! point lights, as the paper's HEPTANE has two), time per pass (one
//! sample in every pixel): plain DVR (`visopt` with `optimise = false`), the optimisation on
//! camera rays only (`light_samples = 0`), full `visopt` (200-sample light
//! lists), and one frame of the deterministic ray-marched AZD17 baseline
//! (normalised, step 0.01: its cost grows with the square of the step
//! count, camera and shadow rays) — measured interleaved in one run, as
//! ratios to DVR; then the camera lists'
//! build time and memory at three resolutions (the paper's Table 3 pool
//! sizes, which it measures on a GPU at 800², 1600², 1920×1080).

use crate::harness::protocol::{render_at, set};
use crate::harness::timing::clocked;
use crate::harness::Writer;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

pub const DEFAULT_SPP: u64 = 64;
const WIDTH: u32 = 64;
const REPEATS: usize = 3;

/// The HEPTANE stand-in of this study and `visopt-equal-time`: a 128³
/// procedural cloud in [−1, 1]³ with its dense core important and two
/// point lights, seen at `width`² through pixel centres.
pub fn heptane_standin(width: u32, extra: &[&str]) -> Result<Scene, String> {
    heptane_standin_sized(width, width, extra)
}

/// [`heptane_standin`] at `width`×`height`.
pub fn heptane_standin_sized(width: u32, height: u32, extra: &[&str]) -> Result<Scene, String> {
    let text = format!(
        "[camera]\nfrom = [0.0, 0.4, 3.2]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = {width}\nheight = {height}\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 128, seed = 11 }}\nsigma_t_scale = 6.0\n\
         albedo = [0.9, 0.9, 0.9]\nfilter = \"trilinear\"\nto_world = {{ scale = 2.0 }}\n\
         [[media.importance]]\nextinction = [3.0, 1e9]\n\
         [[lights]]\ntype = \"point\"\nposition = [2.5, 2.5, 2.0]\nintensity = [20.0, 18.0, 16.0]\n\
         [[lights]]\ntype = \"point\"\nposition = [-2.5, 1.0, 2.0]\nintensity = [8.0, 9.0, 12.0]\n\
         [render]\npixel_jitter = false\n"
    );
    let desc = parse_scene(&text, "heptane stand-in", &set(extra)).map_err(|e| e.to_string())?;
    Scene::build(desc, Path::new(".")).map_err(|e| e.to_string())
}

/// (method, overrides) of the timed methods; AZD17's deterministic
/// marcher needs one frame.
const METHODS: [(&str, &[&str]); 4] = [
    (
        "DVR (no optimisation)",
        &["integrator.type=\"visopt\"", "integrator.optimise=false"],
    ),
    (
        "visopt, camera rays only",
        &["integrator.type=\"visopt\"", "integrator.light_samples=0"],
    ),
    (
        "visopt (200 light samples)",
        &["integrator.type=\"visopt\""],
    ),
    (
        "AZD17 ray marching, step 0.01 (one frame)",
        &["integrator.type=\"ament\"", "integrator.step=0.01"],
    ),
];

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let spp = trials.unwrap_or(DEFAULT_SPP) as u32;
    let lines = pass_times(w, spp)?;
    let mem_lines = list_memory(w)?;
    Ok(format!(
        "Lerzer and Dachsbacher 2025 Fig. 5 (right) / Table 3 on the CPU (2 threads): a 128³ procedural cloud in [−1, 1]³ with two point \
         lights, {WIDTH}², seconds per pass (one sample in every pixel) over {spp} passes (AZD17: its one deterministic frame), best of {REPEATS} interleaved runs (the lists are built before timing).\n\n\
         | method | seconds per pass | / DVR |\n|---|---|---|\n{}\n\n\
         The paper (GPU, HEPTANE, equal quality rather than equal spp): DVR 3.48 s, optimisation without light rays \
         10.08 s (2.9×); SCRAMBLER 21.80 → 24.54 s (1.13×).\n\n\
         Camera lists (1 uniform + 3 adaptive passes of 64 samples, 16-byte entries):\n\n\
         | image | build s | pool MB | entries per pixel |\n|---|---|---|---|\n{}\n\n\
         The paper's Table 3 pools (HEPTANE, 800²): 544 MB with room for every segment to split, 14 entries per pixel.",
        lines.join("\n"),
        mem_lines.join("\n")
    ))
}

/// Seconds per pass of each of [`METHODS`] over `spp` passes, best of
/// [`REPEATS`] interleaved runs with the lists built before timing, into
/// `times.csv`; returns the Markdown lines.
fn pass_times(w: &mut Writer, spp: u32) -> Result<Vec<String>, String> {
    let scenes: Vec<Scene> = METHODS
        .iter()
        .map(|(_, e)| heptane_standin(WIDTH, e))
        .collect::<Result<_, _>>()?;
    for s in &scenes {
        s.integrator.prepare(&s.world);
    }
    let mut best = vec![f64::INFINITY; scenes.len()];
    for _ in 0..REPEATS {
        for (i, s) in scenes.iter().enumerate() {
            // The deterministic marcher needs one frame.
            let n = if i == 3 { 1 } else { spp };
            let r = render_at(s, n, 1);
            best[i] = best[i].min(r.seconds / n as f64);
        }
    }
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    for (i, (name, _)) in METHODS.iter().enumerate() {
        rows.push(vec![
            name.to_string(),
            format!("{:.5}", best[i]),
            format!("{:.3}", best[i] / best[0]),
        ]);
        lines.push(format!(
            "| {name} | {:.4} | {:.2}× |",
            best[i],
            best[i] / best[0]
        ));
    }
    w.csv(
        "times.csv",
        &["method", "seconds_per_spp", "ratio_to_dvr"],
        &rows,
    )?;
    Ok(lines)
}

/// The camera lists' build time and memory at 100², 200² and 400², into
/// `lists.csv`; returns the Markdown lines.
fn list_memory(w: &mut Writer) -> Result<Vec<String>, String> {
    let mut mem = Vec::new();
    let mut mem_lines = Vec::new();
    for width in [100u32, 200, 400] {
        let s = heptane_standin(width, &["integrator.type=\"visopt\""])?;
        let IntegratorKind::VisOpt(v) = &s.integrator else {
            return Err("not visopt".into());
        };
        let (lists, secs) = clocked(|| v.lists(&s.world));
        let px = (width * width) as f64;
        let mb = lists.memory_bytes() as f64 / 1e6;
        let per_pixel = lists.pool.len() as f64 / px;
        mem.push(vec![
            width.to_string(),
            format!("{secs:.3}"),
            format!("{mb:.2}"),
            format!("{per_pixel:.2}"),
        ]);
        mem_lines.push(format!(
            "| {width}² | {secs:.2} | {mb:.2} | {per_pixel:.1} |"
        ));
    }
    w.csv(
        "lists.csv",
        &["width", "build_seconds", "pool_mb", "entries_per_pixel"],
        &mem,
    )?;
    Ok(mem_lines)
}

//! Lin et al. 2021 Figs. 16, 17 and 22: volumetric ReSTIR against the paper's
//! baseline at equal time, with the paper's protocol (§6): per-frame MSE of
//! single frames (one shaded path per pixel for ReSTIR) averaged over many
//! frames after a warm-up, the baseline's spp matched to ReSTIR's frame
//! time, both rendered with pixel-centre rays against an offline `volpath`
//! reference of the same depth. The baseline is `volpath` with the
//! `restir_baseline` preset (decomposition tracking, residual ratio tracking
//! NEE, light sampling only, roulette by albedo) and super-voxels of 8³.
//!
//! Cases (fogbank's stand-ins, no downloads): the procedural cloud under
//! the sky probe at K = 1, 3, 7 (the paper's light-probe cloud); a second
//! cloud lit by a sun and a dim sky; the Houdini dragon of `data/`
//! (a real smoke simulation, standing in for the plume) at K = 3; the
//! procedural explosion (emissive) at K = 2, 4.
//!
//! Reported per case: frame times (ReSTIR's frames timed in turn with the
//! baseline's 1-spp frames), per-frame MSE (the reference's own variance
//! subtracted) in colour and in luminance (Fig. 19's monochrome MSE, blind
//! to the colour noise of a scalar target), the matched-spp MSE ratio
//! baseline/ReSTIR, and the ratio with the baseline extrapolated to exactly
//! ReSTIR's frame time (its MSE falls as 1/spp), which does not depend on
//! rounding the spp. The MSE-vs-time curves of accumulated frames (Fig. 22)
//! go to a log-log plot.

use super::race::{equal_time_race, Rival};
use super::scenes::{Motion, Shot};
use super::sequence::{build_frames, frame_references, rgb};
use crate::harness::protocol::{build, render_at, scenes_dir, set, spp, Frames, Reference};
use crate::harness::timing::clocked;
use crate::harness::SceneText;
use crate::harness::Writer;
use fogbank_eval::plot::{palette, Corner, Figure, LinePlot, Mark, Series};
use fogbank_render::integrators::restir::frame::{PassTimes, Sequence};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::Scene;

/// Reference pixel samples (`--trials` overrides).
pub const DEFAULT_REFERENCE_SPP: u64 = 256;
/// Frames before measuring (temporal reuse fills up) and measured frames.
pub const WARM_UP: u32 = 8;
pub const FRAMES: u32 = 16;
/// Spatial reuse radius in pixels: the paper's 10 px are 0.5 % of its
/// 1920-px width; at this experiment's 128 px that is under one pixel, so
/// the smallest radius that still reaches distinct neighbours stands in
/// (`restir-ablation` measures 5, 10, 20 and 40 px).
pub const RADIUS: f32 = 2.0;

/// One scene at one depth K; a scene with an `[animation]` is measured
/// over its frames ([`measure_animated`]).
pub struct Case {
    pub name: &'static str,
    pub scene: String,
    pub k: u32,
    /// ReSTIR's overrides beyond the defaults (none: the paper's method).
    pub restir: &'static [&'static str],
}

impl Case {
    fn animated(&self) -> bool {
        self.scene.contains("[animation]")
    }
}

fn cloud(lights: &str, seed: u32, scale: f32) -> String {
    format!(
        "[camera]\nfrom = [0.0, 0.1, 2.0]\nto = [0.0, 0.0, 0.0]\nfov = 40.0\nwidth = 128\nheight = 96\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 128, seed = {seed} }}\n\
         sigma_t_scale = {scale}\nalbedo = [0.95, 0.95, 0.95]\nphase = {{ type = \"hg\", g = 0.5 }}\n\
         {lights}\n[render]\npixel_jitter = false\n"
    )
}

fn cases() -> Result<Vec<Case>, String> {
    let mut v = paper_cases()?;
    let pairwise = pairwise_cases(&v);
    v.extend(pairwise);
    Ok(v)
}

/// The stand-ins of the paper's equal-time cases (Figs. 16 and 17).
fn paper_cases() -> Result<Vec<Case>, String> {
    let probe = "[[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n";
    let sun = "[[lights]]\ntype = \"directional\"\ndirection = [-0.4, -0.8, -0.3]\nirradiance = [3.0, 2.9, 2.7]\n\
               [[lights]]\ntype = \"constant\"\nradiance = [0.2, 0.25, 0.35]\n";
    let explosion = explosion()?;
    let mut v = Vec::new();
    for k in [1, 3, 7] {
        v.push(Case {
            name: "probe cloud",
            scene: cloud(probe, 7, 40.0),
            k,
            restir: &[],
        });
    }
    v.push(Case {
        name: "sunlit cloud",
        scene: cloud(sun, 3, 20.0),
        k: 3,
        restir: &[],
    });
    v.push(Case {
        name: "dragon smoke",
        scene: dragon(),
        k: 3,
        restir: &[],
    });
    let still = still_plume()?;
    for k in [3, 7] {
        v.push(Case {
            name: "plume, still",
            scene: still.clone(),
            k,
            restir: &[],
        });
    }
    v.push(Case {
        name: "animated plume",
        scene: animated_plume()?,
        k: 3,
        restir: &[],
    });
    for k in [2, 4] {
        v.push(Case {
            name: "explosion",
            scene: explosion.clone(),
            k,
            restir: &[],
        });
    }
    Ok(v)
}

/// The Houdini dragon of `data/` (a real smoke simulation, standing in for
/// the plume) under the sky probe.
fn dragon() -> String {
    "[camera]\nfrom = [3.0, 4.5, 13.0]\nto = [5.0, 2.5, 5.0]\nfov = 40.0\nwidth = 128\nheight = 96\n\
        [[media]]\ndensity = { vdb = \"../data/dragon.vdb\", grid = \"density\" }\n\
        sigma_t_scale = 8.0\nalbedo = [0.9, 0.9, 0.9]\n\
        [[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\n[render]\npixel_jitter = false\n"
        .to_string()
}

/// The shipped `scenes/explosion.toml` at 128×96 with pixel-centre rays and
/// no integrator of its own.
fn explosion() -> Result<String, String> {
    Ok(SceneText::read(&scenes_dir().join("explosion.toml"))?
        .replace("width = 480", "width = 128")?
        .replace("height = 400", "height = 96")?
        .replace("[render]\nspp = 128", "[render]\npixel_jitter = false")?
        .replace("[integrator]\ntype = \"volpath\"\nmax_depth = 8\n", "")?
        .text())
}

/// The paper's equal-time Plume (Fig. 17, K up to 7) under its protocol
/// ("scenes are static unless noted"): frame 0 of fogbank's procedural
/// plume, held still.
fn still_plume() -> Result<String, String> {
    let still = Shot {
        motion: Motion::Plume { fps: 24.0 },
        frames: 1,
        k: 3,
        width: 128,
        height: 96,
    }
    .text();
    Ok(SceneText::new(
        &still[..still.find("[animation]").unwrap_or(still.len())],
        "the still plume",
    )
    .replace(
        "[integrator]\ntype = \"restir\"\nmax_depth = 3\nradius = 2.0\n",
        "",
    )?
    .text())
}

/// The plume animated too (Fig. 4's Plume is dynamic): 24 fps, as
/// `restir-dynamic` renders it.
fn animated_plume() -> Result<String, String> {
    let plume = Shot {
        motion: Motion::Plume { fps: 24.0 },
        frames: WARM_UP + FRAMES,
        k: 3,
        width: 128,
        height: 96,
    };
    Ok(SceneText::new(plume.text(), "the animated plume")
        .replace(
            "[integrator]\ntype = \"restir\"\nmax_depth = 3\nradius = 2.0\n",
            "",
        )?
        .text())
}

/// Beyond the paper: pairwise MIS in the reuse passes (2N instead of
/// N(N + 1) target evaluations), on the cases of `v` where ReSTIR is
/// closest to or behind the baseline.
fn pairwise_cases(v: &[Case]) -> Vec<Case> {
    const PAIRWISE: &[&str] = &["integrator.mis=pairwise"];
    v.iter()
        .filter(|c| {
            (c.name == "probe cloud" && c.k < 7)
                || c.name == "dragon smoke"
                || c.name == "plume, still" && c.k == 3
        })
        .map(|c| Case {
            name: match c.name {
                "probe cloud" => "probe cloud, pairwise MIS",
                "dragon smoke" => "dragon smoke, pairwise MIS",
                _ => "plume, still, pairwise MIS",
            },
            scene: c.scene.clone(),
            k: c.k,
            restir: PAIRWISE,
        })
        .collect()
}

struct Measured {
    /// The reference image and its size.
    reference: Vec<[f32; 3]>,
    size: (u32, u32),
    restir: Frames,
    baseline: Rival,
}

/// The `--set` overrides of case `c`'s renders: the reference (`volpath`
/// at depth K), ReSTIR, and the baseline (`volpath` with the paper's
/// preset and 8³ super-voxels).
fn overrides(c: &Case) -> [Vec<String>; 3] {
    let depth = format!("integrator.max_depth={}", c.k);
    let radius = format!("integrator.radius={RADIUS}");
    [
        set(&["integrator.type=volpath", &depth]),
        [
            set(&["integrator.type=restir", &depth, &radius]),
            set(c.restir),
        ]
        .concat(),
        set(&[
            "integrator.type=volpath",
            "integrator.preset=restir_baseline",
            "media.0.supervoxel=8",
            &depth,
        ]),
    ]
}

fn measure(c: &Case, reference_spp: u32) -> Result<Measured, String> {
    if c.animated() {
        return measure_animated(c, reference_spp);
    }
    let [reference_set, restir_set, baseline_set] = overrides(c);
    let reference = Reference::render(
        &build(&c.scene, &reference_set)?,
        reference_spp,
        0x5EED_0002,
    );
    let restir_scene = build(&c.scene, &restir_set)?;
    let baseline_scene = build(&c.scene, &baseline_set)?;
    let (restir, rivals) = equal_time_race(
        &restir_scene,
        &[&baseline_scene],
        &reference,
        WARM_UP,
        FRAMES,
        0x5EED_0003,
        1000,
    );
    let baseline = rivals.into_iter().next().expect("one rival");
    Ok(Measured {
        size: (restir_scene.camera.width, restir_scene.camera.height),
        reference: reference.rgb.clone(),
        restir,
        baseline,
    })
}

/// [`measure`] over an animated scene's frames, each against its own
/// `volpath` reference: ReSTIR's sequence reuses from frame to frame while
/// the baseline renders each frame afresh; every ReSTIR frame is timed in
/// turn with a baseline frame (1 spp during the warm-up, to pick the spp,
/// then that spp), as [`equal_time_race`] does for a still scene. No
/// MSE-vs-time curve: accumulating frames of a moving scene is not a
/// convergence.
fn measure_animated(c: &Case, reference_spp: u32) -> Result<Measured, String> {
    let n = WARM_UP + FRAMES;
    let [reference_set, restir_set, baseline_set] = overrides(c);
    let refs = frame_references(&c.scene, &reference_set, 0..n, reference_spp, 0x5EED_0002)?;
    let restir = build_frames(&c.scene, &restir_set, n)?;
    let baseline = build_frames(&c.scene, &baseline_set, n)?;
    let (frames, rival) = race_frames(&restir, &baseline, &refs)?;
    Ok(Measured {
        size: (restir[0].camera.width, restir[0].camera.height),
        reference: refs.last().expect("frames").rgb.clone(),
        restir: frames,
        baseline: rival,
    })
}

/// ReSTIR's sequence over the built `restir` frames and the baseline's
/// frames, taking turns, each frame against its reference in `refs`:
/// [`WARM_UP`] pilot frames (the baseline at 1 spp), then [`FRAMES`]
/// measured ones (the baseline at the spp the pilot matched).
fn race_frames(
    restir: &[Scene],
    baseline: &[Scene],
    refs: &[Reference],
) -> Result<(Frames, Rival), String> {
    let integrators = restir
        .iter()
        .map(|scene| match &scene.integrator {
            IntegratorKind::Restir(r) => Ok(r),
            _ => Err("the animated case needs the restir integrator".to_string()),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut seq = Sequence::new(integrators[0], 0x5EED_0003, 0);
    let mut restir_frame = |f: usize| {
        let p = f.saturating_sub(1);
        let (cur, old) = (
            integrators[f].data(&restir[f].world),
            integrators[p].data(&restir[p].world),
        );
        let (out, seconds) = clocked(|| seq.frame(&cur, &old));
        (seconds, rgb(&out), out.times)
    };
    let baseline_frame = |f: usize, spp: u32, seed: u32| {
        let (img, seconds) = clocked(|| render_at(&baseline[f], spp, seed).film.mean());
        (seconds, img)
    };
    let (mut r, mut one, mut b) = (Tally::default(), Tally::default(), Tally::default());
    let (mut r_pilot, mut passes) = (0.0, PassTimes::default());
    for (f, reference) in refs.iter().enumerate().take(WARM_UP as usize) {
        r_pilot += restir_frame(f).0;
        let (t, img) = baseline_frame(f, 1, 1000 + f as u32);
        one.add(t, &img, reference);
    }
    let spp = ((r_pilot / one.seconds).round() as u32).max(1);
    for (f, reference) in refs.iter().enumerate().skip(WARM_UP as usize) {
        let (t, img, times) = restir_frame(f);
        r.add(t, &img, reference);
        for (sum, x) in [
            (&mut passes.candidates, times.candidates),
            (&mut passes.temporal, times.temporal),
            (&mut passes.spatial, times.spatial),
            (&mut passes.shading, times.shading),
        ] {
            *sum += x / FRAMES as f64;
        }
        let (t, img) = baseline_frame(f, spp, 2000 + f as u32);
        b.add(t, &img, reference);
    }
    Ok((
        r.finish(passes),
        Rival {
            one_spp: one.finish(PassTimes::default()),
            spp,
            frames: b.finish(PassTimes::default()),
        },
    ))
}

/// Per-frame MSEs and times of frames each compared with its own reference.
#[derive(Default)]
struct Tally {
    n: u32,
    seconds: f64,
    mse: f64,
    mono_mse: f64,
    last: Vec<[f32; 3]>,
}

impl Tally {
    fn add(&mut self, seconds: f64, img: &[[f32; 3]], reference: &Reference) {
        self.n += 1;
        self.seconds += seconds;
        self.mse += reference.mse(img);
        self.mono_mse += reference.mono_mse(img);
        self.last = img.to_vec();
    }

    fn finish(self, passes: PassTimes) -> Frames {
        let n = self.n.max(1) as f64;
        Frames {
            ms: 1e3 * self.seconds / n,
            mse: self.mse / n,
            mono_mse: self.mono_mse / n,
            curve: Vec::new(),
            passes,
            last: self.last,
        }
    }
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    run_cases(
        w,
        trials,
        &cases()?,
        "Lin et al. 2021 Fig. 22: MSE of accumulated frames vs time (solid ReSTIR, dashed baseline)",
        |threads, reference_spp| {
            format!(
                "Lin et al. 2021 Figs. 16/17 (equal time) on fogbank's CPU backend ({threads} threads), \
                 128×96, pixel-centre rays, spatial radius {RADIUS} px, {WARM_UP} warm-up + {FRAMES} measured frames, \
                 reference `volpath` at {reference_spp} spp (its variance subtracted from every MSE). \
                 The paper reports lower MSE for ReSTIR than the baseline in every case, on an RTX 3090 at 1920×1080; \
                 fogbank's own goal is ≥ 4× on the light-probe cloud at K = 1 and lower at every K."
            )
        },
    )
}

/// An equal-time run: `cases` measured by [`compare`] against a `volpath`
/// reference at the trials' spp, the table under `note(threads,
/// reference spp)`.
pub fn run_cases(
    w: &mut Writer,
    trials: Option<u64>,
    cases: &[Case],
    figure_title: &str,
    note: impl FnOnce(usize, u32) -> String,
) -> Result<String, String> {
    let reference_spp = spp(trials, DEFAULT_REFERENCE_SPP);
    let table = compare(w, cases, reference_spp, figure_title)?;
    let note = note(rayon::current_num_threads(), reference_spp);
    Ok(format!("{note}\n\n{table}"))
}

/// Measures every case, writes `equal_time.csv` and the Fig. 22 curves
/// (`mse_vs_time`, titled `figure_title`) and returns the Markdown table
/// with its note.
pub fn compare(
    w: &mut Writer,
    cases: &[Case],
    reference_spp: u32,
    figure_title: &str,
) -> Result<String, String> {
    let threads = rayon::current_num_threads();
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    let mut images = Vec::new();
    let (width, height) = cases
        .first()
        .and_then(|c| build(&c.scene, &[]).ok())
        .map_or((0, 0), |s| (s.camera.width, s.camera.height));
    let mut plot = LinePlot::new(
        format!("accumulated frames, {threads} threads, {width}x{height}"),
        "time (s)",
        "MSE",
    )
    .log_x()
    .log_y()
    .legend(Corner::LowerLeft);
    for (i, c) in cases.iter().enumerate() {
        let m = measure(c, reference_spp).map_err(|e| format!("{} K={}: {e}", c.name, c.k))?;
        let (row, line) = case_row(c, &m);
        rows.push(row);
        lines.push(line);
        let (r, b) = (&m.restir, &m.baseline.frames);
        let label = format!("{} K={}", c.name, c.k);
        // One frame of each at equal time beside the reference.
        let file = format!("frames_{i}.png");
        let exposure = Writer::auto_exposure(&m.reference);
        let panels = [&r.last[..], &b.last[..], &m.reference[..]];
        w.png_strip(&file, m.size.0, m.size.1, &panels, exposure)?;
        images.push(format!("`{file}`: {label}"));
        if r.curve.is_empty() {
            continue;
        }
        plot = plot
            .with(Series::new(
                format!("ReSTIR {label}"),
                r.curve.clone(),
                palette(i),
                Mark::LinePoints,
            ))
            .with(Series::new(
                format!("baseline {label}"),
                b.curve.clone(),
                palette(i),
                Mark::Dashed,
            ));
    }
    w.csv("equal_time.csv", &HEADER, &rows)?;
    w.figure(
        "mse_vs_time",
        &Figure::new(1)
            .panel_size(900, 640)
            .title(figure_title)
            .with(plot),
    )?;
    Ok(note(&lines, &images))
}

/// The Markdown table of `compare` with its note on the protocol and the
/// images.
fn note(lines: &[String], images: &[String]) -> String {
    format!(
        "| case | K | ReSTIR ms/frame | ReSTIR MSE | baseline spp (ms/frame) | baseline MSE | ratio at matched spp | ratio at equal time | ReSTIR mono MSE | mono ratio at equal time |\n\
         |---|---|---|---|---|---|---|---|---|---|\n{}\n\n\
         Each ReSTIR frame is timed in turn with a baseline frame. \"matched\": the baseline's MSE at the spp its 1-spp frames \
         (timed with ReSTIR's warm-up) matched to ReSTIR's frame time; \"at equal time\" scales that MSE by the two measured frame \
         times (MSE ∝ 1/time for the baseline's independent samples). \"mono\": the MSE of the error's \
         luminance (Lin et al. 2021 Fig. 19's monochrome images), blind to the colour noise of ReSTIR's scalar target \
         (§6.2: every channel follows one luminance-sampled path).\n\n\
         One frame of ReSTIR, one of the baseline at the matched spp, and the reference, left to right: {}.",
        lines.join("\n"),
        images.join("; ")
    )
}

/// The columns of `equal_time.csv`.
const HEADER: [&str; 14] = [
    "case",
    "K",
    "restir_ms",
    "restir_mse",
    "baseline_spp",
    "baseline_ms",
    "baseline_mse",
    "mse_ratio_matched",
    "baseline_1spp_ms",
    "baseline_1spp_mse",
    "mse_ratio_equal_time",
    "restir_mono_mse",
    "baseline_mono_mse",
    "mono_mse_ratio_equal_time",
];

/// Case `c`'s CSV row and Markdown table line.
fn case_row(c: &Case, m: &Measured) -> (Vec<String>, String) {
    let (r, b, b1) = (&m.restir, &m.baseline.frames, &m.baseline.one_spp);
    let matched = b.mse / r.mse;
    let (extrapolated, mono) = m.baseline.ratios(r);
    let row = vec![
        c.name.to_string(),
        c.k.to_string(),
        format!("{:.2}", r.ms),
        format!("{:.4e}", r.mse),
        m.baseline.spp.to_string(),
        format!("{:.2}", b.ms),
        format!("{:.4e}", b.mse),
        format!("{matched:.2}"),
        format!("{:.2}", b1.ms),
        format!("{:.4e}", b1.mse),
        format!("{extrapolated:.2}"),
        format!("{:.4e}", r.mono_mse),
        format!("{:.4e}", b.mono_mse),
        format!("{mono:.2}"),
    ];
    let line = format!(
        "| {} | {} | {:.1} | {:.3e} | {} ({:.1} ms) | {:.3e} | {matched:.2}× | {extrapolated:.2}× | {:.3e} | {mono:.2}× |",
        c.name, c.k, r.ms, r.mse, m.baseline.spp, b.ms, b.mse, r.mono_mse
    );
    (row, line)
}

#[cfg(test)]
mod restir_equal_time_test {
    use super::*;

    /// Every case's scene, the shipped explosion adapted by its edits
    /// included, reads as a scene.
    #[test]
    fn every_case_reads_as_a_scene() {
        for c in cases().unwrap() {
            fogbank_render::parse_scene(&c.scene, c.name, &[]).unwrap();
        }
    }
}

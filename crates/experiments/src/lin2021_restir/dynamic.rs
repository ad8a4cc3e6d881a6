//! Lin et al. 2021's studies of moving scenes and of accumulation, with the
//! protocol of `harness::protocol` and per-frame `volpath` references:
//! - Fig. 8: spatial reuse only, temporal reuse without reprojection (the
//!   same pixel) and with reprojection, under camera motion (an orbit) and
//!   deformation (the animated plume);
//! - Fig. 13: velocity resampling off (background samples follow the
//!   background's motion) and on, with the signed error in a band of
//!   background pixels along the silhouette (the paper's bright halo);
//! - Fig. 14: Q = 1, 4, 20 under a fast lighting change (a sun turning 30°
//!   per frame), with a firefly count;
//! - Fig. 20: colour and monochrome error of the mean of 1 … 64 frames of a
//!   static scene (the scalar target's colour noise falls as frames
//!   accumulate);
//! - memory per pixel of the frame's reservoirs.

use super::scenes::{Motion, Shot};
use super::sequence::{build_frames, frame_references, restir_sequence, rgb};
use crate::harness::protocol::{build, independent_frames, lum, mono_mse, set, spp, Reference};
use crate::harness::Writer;
use fogbank_render::integrators::restir::path::PathSample;
use fogbank_render::integrators::restir::reservoir::Reservoir;
use fogbank_render::integrators::restir::volume::SegmentT;
use fogbank_render::Scene;

const WARM_UP: u32 = 8;
const MEASURED: u32 = 16;
const SEED: u32 = 0x5EED_0020;

/// (figure, scene, motion, [(configuration, overrides)]).
/// Figs. 8 and 13's configurations under camera motion or deformation.
const MOTION_CONFIGS: &[(&str, &[&str])] = &[
    ("spatial only", &["integrator.reuse=spatial"]),
    (
        "temporal without reprojection",
        &["integrator.reprojection=false"],
    ),
    (
        "velocity resampling off",
        &["integrator.velocity_resampling=false"],
    ),
    ("reprojection + velocity resampling", &[]),
];

type Study<'a> = (&'a str, &'a str, Motion, &'a [(&'a str, &'a [&'a str])]);

/// The studies of moving scenes: Figs. 8 and 13 under an orbit, the
/// deforming plume and a drift; Fig. 14 under a sweeping sun.
const STUDIES: &[Study] = &[
    (
        "8, 13",
        "orbit",
        Motion::Orbit {
            degrees: 2.0,
            stop: u32::MAX,
        },
        MOTION_CONFIGS,
    ),
    ("8, 13", "plume", Motion::Plume { fps: 8.0 }, MOTION_CONFIGS),
    (
        "8",
        "drift",
        Motion::Drift { step: 0.02 },
        &[
            ("spatial only", &["integrator.reuse=spatial"]),
            (
                "temporal without reprojection",
                &["integrator.reprojection=false"],
            ),
            ("reprojection + velocity resampling", &[]),
        ],
    ),
    (
        "14",
        "sun sweep 30°/frame",
        Motion::SunSweep { degrees: 30.0 },
        &[
            ("Q = 1", &["integrator.temporal_cap=1"]),
            ("Q = 4", &[]),
            ("Q = 20", &["integrator.temporal_cap=20"]),
        ],
    ),
];

/// Background pixels (primary transmittance ≥ 0.9) within 2 px of a
/// medium pixel: where a silhouette halo shows.
fn silhouette_band(scene: &Scene) -> Vec<bool> {
    let cam = &scene.camera;
    let (w, h) = (cam.width as i32, cam.height as i32);
    let m = &scene.media[0].medium;
    let medium: Vec<bool> = (0..w * h)
        .map(|i| {
            let ray = cam.ray((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            SegmentT::Exact.eval(m, &ray, f32::INFINITY, &mut 0) < 0.9
        })
        .collect();
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            !medium[i as usize]
                && (-2..=2).any(|dy| {
                    (-2..=2).any(|dx| {
                        let (u, v) = (x + dx, y + dy);
                        u >= 0 && v >= 0 && u < w && v < h && medium[(v * w + u) as usize]
                    })
                })
        })
        .collect()
}

/// What one configuration measured over the frames after the warm-up.
struct Run {
    ms: f64,
    mse: f64,
    /// Mean signed luminance error in the silhouette band, relative to the
    /// reference's mean luminance there.
    halo: f64,
    /// Pixels per thousand whose luminance error exceeds 4× the mean
    /// reference luminance.
    fireflies: f64,
    last: Vec<[f32; 3]>,
}

fn measure(frames: &[Scene], refs: &[Reference]) -> Run {
    let bands: Vec<Vec<bool>> = frames[WARM_UP as usize..]
        .iter()
        .map(silhouette_band)
        .collect();
    let (mut ms, mut mse, mut halo, mut fireflies) = (0.0, 0.0, 0.0, 0.0);
    let mut last = Vec::new();
    restir_sequence(frames, SEED, 0, |i, out| {
        let Some(j) = i.checked_sub(WARM_UP as usize) else {
            return;
        };
        let img = rgb(&out);
        let r = &refs[j];
        let t = &out.times;
        ms += 1e3 * (t.candidates + t.temporal + t.spatial + t.shading);
        mse += r.mse(&img);
        let (mut err, mut base) = (0.0, 0.0);
        for (k, _) in bands[j].iter().enumerate().filter(|b| *b.1) {
            err += lum(&img[k]) - lum(&r.rgb[k]);
            base += lum(&r.rgb[k]);
        }
        halo += if base > 0.0 { err / base } else { 0.0 };
        let mean = r.rgb.iter().map(lum).sum::<f64>() / r.rgb.len() as f64;
        let hot = img
            .iter()
            .zip(&r.rgb)
            .filter(|(a, b)| (lum(a) - lum(b)).abs() > 4.0 * mean)
            .count();
        fireflies += 1e3 * hot as f64 / img.len() as f64;
        last = img;
    });
    let n = MEASURED as f64;
    Run {
        ms: ms / n,
        mse: mse / n,
        halo: halo / n,
        fireflies: fireflies / n,
        last,
    }
}

fn shot(motion: Motion) -> Shot {
    Shot {
        motion,
        frames: WARM_UP + MEASURED,
        k: 3,
        width: 128,
        height: 96,
    }
}

pub fn run(w: &mut Writer, trials: Option<u64>) -> Result<String, String> {
    let reference_spp = spp(trials, 64);
    let threads = rayon::current_num_threads();
    let mut rows = Vec::new();
    let mut table = Vec::new();
    for study in STUDIES {
        measure_study(w, study, reference_spp, &mut rows, &mut table)?;
    }
    w.csv(
        "dynamic.csv",
        &[
            "figure",
            "scene",
            "configuration",
            "ms_per_frame",
            "mse",
            "silhouette_error",
            "fireflies_per_mille",
        ],
        &rows,
    )?;
    let accumulation = accumulation(w, reference_spp.max(256))?;
    let memory = memory_per_pixel();
    Ok(format!(
        "Lin et al. 2021's dynamic studies on fogbank's CPU backend ({threads} threads): 128×96, K = 3, spatial radius 2 px, \
         {WARM_UP} warm-up + {MEASURED} measured frames of one sequence, each against its own `volpath` reference \
         at {reference_spp} spp (variance subtracted). The orbit turns the camera 2° per frame about the cloud; \
         the plume plays at 8 fps (its matter rises 0.019 box heights, about 1.7 px, and swirls 0.1 rad per frame, while its envelope stays put); \
         the drifting cloud moves sideways 0.02 units (about 1.8 px) per frame; the sun turns 30° per frame. \
         \"silhouette error\" is the mean signed luminance error over background pixels within 2 px of the medium, \
         relative to the reference there (the paper's Fig. 13 halo is a positive error); \"fireflies\" counts pixels per \
         thousand whose luminance error exceeds 4× the image's mean luminance. Images: `<scene>_<row>.png` (last frame), \
         `<scene>_reference.png`.\n\n\
         | fig. | scene | configuration | ms/frame | MSE | silhouette error | fireflies ‰ |\n|---|---|---|---|---|---|---|\n{}\n\n{accumulation}\n\n{memory}\n",
        table.join("\n")
    ))
}

/// One study: per-frame references from `reference_spp` spp (the last
/// written as `<scene>_reference.png`), then each configuration's frames
/// (its last as `<scene>_<row>.png`), its CSV row into `rows` and its
/// Markdown line into `table`.
fn measure_study(
    w: &mut Writer,
    (fig, name, motion, configs): &Study,
    reference_spp: u32,
    rows: &mut Vec<Vec<String>>,
    table: &mut Vec<String>,
) -> Result<(), String> {
    let sh = shot(*motion);
    let text = sh.text();
    let refs = frame_references(&text, &[], WARM_UP..sh.frames, reference_spp, 0x5EED_0021)?;
    let stem = name.split(' ').next().unwrap_or("scene");
    w.png(
        &format!("{stem}_reference.png"),
        sh.width,
        sh.height,
        &refs[refs.len() - 1].rgb,
        0.0,
    )?;
    for (i, (label, overrides)) in configs.iter().enumerate() {
        let frames = build_frames(&text, &set(overrides), sh.frames)?;
        let r = measure(&frames, &refs);
        w.png(
            &format!("{stem}_{i}.png"),
            sh.width,
            sh.height,
            &r.last,
            0.0,
        )?;
        table.push(format!(
            "| {fig} | {name} | {label} | {:.1} | {:.3e} | {:+.2} % | {:.2} |",
            r.ms,
            r.mse,
            100.0 * r.halo,
            r.fireflies
        ));
        rows.push(vec![
            fig.to_string(),
            name.to_string(),
            label.to_string(),
            format!("{:.2}", r.ms),
            format!("{:.5e}", r.mse),
            format!("{:.5}", r.halo),
            format!("{:.3}", r.fireflies),
        ]);
    }
    Ok(())
}

/// Fig. 20: the mean of N frames of one sequence of the static cloud, with
/// its colour, monochrome and chroma error, beside the baseline's.
fn accumulation(w: &mut Writer, reference_spp: u32) -> Result<String, String> {
    let sh = shot(Motion::Still);
    let text = sh.text();
    let reference = Reference::render(
        &build(&text, &set(&["integrator.type=volpath"]))?,
        reference_spp,
        0x5EED_0022,
    );
    let total = 64u32;
    let frames = build_frames(&text, &[], 1)?;
    let static_frames: Vec<Scene> = (0..WARM_UP + total).map(|_| frames[0].clone()).collect();
    let mut acc = vec![[0.0f64; 3]; reference.rgb.len()];
    let mut lines = Vec::new();
    let mut rows = Vec::new();
    restir_sequence(&static_frames, SEED, 1, |i, out| {
        let Some(j) = i.checked_sub(WARM_UP as usize) else {
            return;
        };
        for (a, p) in acc.iter_mut().zip(rgb(&out)) {
            for c in 0..3 {
                a[c] += p[c] as f64;
            }
        }
        let n = j as u32 + 1;
        if n.is_power_of_two() {
            let mean: Vec<[f32; 3]> = acc
                .iter()
                .map(|a| a.map(|x| (x / n as f64) as f32))
                .collect();
            let (colour, mono, chroma) = errors(&mean, &reference);
            lines.push(format!(
                "| {n} | {colour:.3e} | {mono:.3e} | {chroma:.3e} | {:.2} |",
                chroma / mono
            ));
            rows.push(vec![
                n.to_string(),
                format!("{colour:.5e}"),
                format!("{mono:.5e}"),
                format!("{chroma:.5e}"),
            ]);
        }
    });
    w.csv(
        "accumulation.csv",
        &["frames", "colour_mse", "mono_mse", "chroma_mse"],
        &rows,
    )?;
    let baseline = build(
        &text,
        &set(&[
            "integrator.type=volpath",
            "integrator.max_depth=3",
            "integrator.preset=restir_baseline",
            "media.0.supervoxel=8",
        ]),
    )?;
    let b = independent_frames(&baseline, &reference, 1, 1, 0x5EED_0023);
    let (colour, mono, chroma) = errors(&b.last, &reference);
    Ok(format!(
        "Fig. 20: the mean of N frames of one ReSTIR sequence of the static cloud ({WARM_UP} warm-up frames first) against a \
         `volpath` reference at {reference_spp} spp. \"chroma\" is the MSE of the error with its luminance removed \
         (e − lum(e)·(1, 1, 1)); the reference's own noise is not subtracted from the mono and chroma columns.\n\n\
         | frames | colour MSE | mono MSE | chroma MSE | chroma / mono |\n|---|---|---|---|---|\n{}\n\n\
         The baseline at 1 spp for comparison: colour {colour:.3e}, mono {mono:.3e}, chroma {chroma:.3e}, chroma / mono {:.2}.",
        lines.join("\n"),
        chroma / mono
    ))
}

/// (colour MSE with the reference floor removed, luminance MSE, chroma MSE).
fn errors(img: &[[f32; 3]], reference: &Reference) -> (f64, f64, f64) {
    let n = img.len() as f64;
    let mut chroma = 0.0;
    for (a, r) in img.iter().zip(&reference.rgb) {
        let e: [f64; 3] = std::array::from_fn(|c| a[c] as f64 - r[c] as f64);
        let l = lum(&e.map(|x| x as f32));
        chroma += e.iter().map(|x| (x - l).powi(2)).sum::<f64>() / 3.0;
    }
    (
        reference.mse(img),
        mono_mse(img, &reference.rgb),
        chroma / n,
    )
}

/// Bytes per pixel of what a frame keeps: the previous frame's reservoirs
/// and the current frame's (candidates, after temporal, after spatial; the
/// passes free each array once the next is built, so two are alive at a
/// time besides the previous one), and the shaded radiance.
fn memory_per_pixel() -> String {
    let reservoir = std::mem::size_of::<Reservoir<PathSample>>();
    let radiance = std::mem::size_of::<[f32; 3]>();
    let total = 3 * reservoir + radiance;
    format!(
        "Memory per pixel (CPU): a reservoir with its path (up to K = 8 vertices stored, MAX_K) is {reservoir} bytes; \
         a frame keeps the previous frame's reservoirs plus two arrays of the current frame and the {radiance}-byte radiance: \
         {total} bytes per pixel, {:.0} MiB at 1920×1080. The reservoirs are sized for K = 8 whatever K is.",
        total as f64 * 1920.0 * 1080.0 / (1u64 << 20) as f64
    )
}

//! Per-pixel statistics of a scene's integrator over K independent 1-spp
//! frames (Peters 2025 §6.1, Figs. 8–10): mean, single-frame standard
//! deviation, and bias against an exact reference.
//!
//! Primary rays go through pixel centres, so an exact estimator gives one
//! reference value per pixel; frame k is sample index k of each pixel's
//! random streams. Each pixel runs its K frames in a row with Welford's
//! update, so memory is independent of K and the result of the thread count.

use crate::Backend;
use fogbank_estimators::Estimator;
use fogbank_math::SampleKey;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::shard::Piece;
use fogbank_render::world::film::{Accumulated, PixelSums};
use fogbank_render::{Film, Scene};
use rayon::prelude::*;
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct FrameStats {
    pub width: u32,
    pub height: u32,
    pub runs: u32,
    /// Per-pixel mean over the runs.
    pub mean: Vec<[f64; 3]>,
    /// Per-pixel variance of a single frame (unbiased, n − 1).
    pub variance: Vec<[f64; 3]>,
    /// Per-pixel finite samples (non-finite ones are dropped and counted).
    pub count: Vec<u32>,
    /// Per-pixel exact values, when a reference was given.
    pub reference: Option<Vec<[f64; 3]>>,
    /// Pixels whose primary ray meets a medium's box; summaries average
    /// over these so empty background does not dilute them.
    pub covered: Vec<bool>,
    pub lookups: u64,
    pub nonfinite: u64,
    pub seconds: f64,
}

/// Image-level figures, averaged over covered pixels and the three channels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    pub mean_abs_bias: f64,
    pub mean_bias: f64,
    /// Standard error of `mean_bias` (pixels are independent): an unbiased
    /// estimator has |mean_bias| within a few of these.
    pub mean_bias_se: f64,
    pub mean_std: f64,
    pub rmse: f64,
    pub ms_per_frame: f64,
    pub lookups_per_pixel: f64,
    pub runs: u32,
    pub pixels: usize,
}

fn centred(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.world.pixel_jitter = false;
    s
}

/// Runs `runs` frames of the scene's integrator through pixel centres on
/// `backend`. The GPU runs the same frames (sample indices, streams),
/// accumulated on the device as running means and M2 in f32, so a constant
/// pixel's variance is 0 there too.
pub fn frame_stats(
    backend: Backend,
    scene: &Scene,
    runs: u32,
    seed: u32,
) -> Result<FrameStats, String> {
    let scene = centred(scene);
    match backend {
        Backend::Cpu => Ok(pixel_frames(&scene, runs, seed)),
        Backend::Gpu(_) => film_frames(backend, &scene, runs, seed),
    }
}

/// The CPU's frames of a centred scene: each pixel runs its frames in a row
/// into exact sums (as a film does), so the statistics of frames split into
/// shards and merged are the same bits.
fn pixel_frames(scene: &Scene, runs: u32, seed: u32) -> FrameStats {
    let start = Instant::now();
    let film = frame_film(scene, &Piece::whole(runs), seed);
    let seconds = start.elapsed().as_secs_f64();
    from_film(&film, runs, covered_pixels(scene), seconds)
}

/// One shard's part of [`frame_stats`] on the CPU: the frames (sample
/// indices) and pixels of `piece`, through pixel centres, as a film whose
/// sums merge exactly with the other parts'; with the covered pixels and
/// the seconds it took.
pub fn frame_stats_piece(scene: &Scene, piece: &Piece, seed: u32) -> (Film, Vec<bool>, f64) {
    let scene = centred(scene);
    let start = Instant::now();
    let film = frame_film(&scene, piece, seed);
    let seconds = start.elapsed().as_secs_f64();
    (film, covered_pixels(&scene), seconds)
}

/// The frames and pixels of `piece` of a centred scene on the CPU,
/// accumulated per pixel into a film.
fn frame_film(scene: &Scene, piece: &Piece, seed: u32) -> Film {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let per_pixel: Vec<(PixelSums, u32, u64, u64, u64)> = (0..(w * h) as usize)
        .into_par_iter()
        .map(|p| {
            let (x, y) = ((p % w as usize) as u32, (p / w as usize) as u32);
            let (mut sums, mut n, mut lookups, mut nan, mut inf) =
                (PixelSums::default(), 0u32, 0u64, 0u64, 0u64);
            let frames = if piece.has_pixel(x, y, w) {
                piece.sample_range()
            } else {
                0..0
            };
            for k in frames {
                let key = SampleKey {
                    seed,
                    pixel: p as u32,
                    sample: k,
                    dimension: 0,
                };
                let s = scene.sample_pixel(x, y, key);
                lookups += s.lookups as u64;
                match sums.add(&mut n, s.radiance) {
                    Accumulated::Added => {}
                    Accumulated::Nan => nan += 1,
                    Accumulated::Inf => inf += 1,
                }
            }
            (sums, n, lookups, nan, inf)
        })
        .collect();
    let mut film = Film::new(w, h);
    for (i, (sums, n, lookups, nan, inf)) in per_pixel.into_iter().enumerate() {
        film.sums[i] = sums;
        film.count[i] = n;
        film.lookups += lookups;
        film.nan_samples += nan;
        film.inf_samples += inf;
    }
    film
}

/// The statistics of `runs` frames from their film: mean, single-frame
/// variance (from the exact sums), counts.
pub fn from_film(f: &Film, runs: u32, covered: Vec<bool>, seconds: f64) -> FrameStats {
    FrameStats {
        width: f.width,
        height: f.height,
        runs,
        mean: (0..f.sums.len())
            .map(|i| {
                let n = f.count[i];
                if n == 0 {
                    [0.0; 3]
                } else {
                    f.sum(i).map(|s| s / n as f64)
                }
            })
            .collect(),
        variance: (0..f.sums.len()).map(|i| f.sample_variance(i)).collect(),
        count: f.count.clone(),
        reference: None,
        covered,
        lookups: f.lookups,
        nonfinite: f.nan_samples + f.inf_samples,
        seconds,
    }
}

/// Pixels whose centre ray meets a medium's box.
fn covered_pixels(scene: &Scene) -> Vec<bool> {
    let w = scene.camera.width as usize;
    (0..w * scene.camera.height as usize)
        .map(|p| {
            let ray = scene.camera.ray((p % w) as f32 + 0.5, (p / w) as f32 + 0.5);
            scene
                .media
                .iter()
                .any(|m| m.medium.to_index(&ray, 0.0, f32::INFINITY).is_some())
        })
        .collect()
}

/// The frames of a centred scene as one render of `runs` spp on `backend`,
/// the statistics from the film's per-pixel sums.
fn film_frames(
    backend: Backend,
    scene: &Scene,
    runs: u32,
    seed: u32,
) -> Result<FrameStats, String> {
    let opts = fogbank_render::RenderOptions::new(runs, seed);
    let r = backend.render(scene, &opts, &fogbank_render::Progress::default())?;
    Ok(from_film(&r.film, runs, covered_pixels(scene), r.seconds))
}

/// One frame of the scene with its estimator replaced by `exact` (a
/// deterministic estimator such as `analytic_trilinear`), through pixel
/// centres.
pub fn exact_reference(scene: &Scene, exact: Estimator) -> Vec<[f64; 3]> {
    let mut s = centred(scene);
    s.integrator = with_estimator(&s.integrator, exact);
    pixel_frames(&s, 1, 0).mean
}

/// The integrator with its transmittance estimator swapped.
pub fn with_estimator(i: &IntegratorKind, e: Estimator) -> IntegratorKind {
    i.with_estimator(e)
}

/// Frame statistics (on the CPU) of the transmittance view with
/// `estimator`, against an exact `reference` estimator when given.
pub fn transmittance_stats(
    scene: &Scene,
    estimator: Estimator,
    reference: Option<Estimator>,
    runs: u32,
    seed: u32,
) -> FrameStats {
    let mut s = scene.clone();
    s.integrator = with_estimator(&s.integrator, estimator);
    let mut st = pixel_frames(&centred(&s), runs, seed);
    st.reference = reference.map(|r| exact_reference(&s, r));
    st
}

impl FrameStats {
    pub fn bias(&self) -> Option<Vec<[f64; 3]>> {
        self.reference.as_ref().map(|r| {
            self.mean
                .iter()
                .zip(r)
                .map(|(m, r)| std::array::from_fn(|c| m[c] - r[c]))
                .collect()
        })
    }

    pub fn summary(&self) -> Summary {
        let idx: Vec<usize> = (0..self.mean.len()).filter(|&p| self.covered[p]).collect();
        let k = (idx.len() * 3).max(1) as f64;
        let bias = self.bias();
        let b = |p: usize, c: usize| bias.as_ref().map_or(0.0, |b| b[p][c]);
        let sum = |f: &dyn Fn(usize, usize) -> f64| {
            idx.iter()
                .flat_map(|&p| (0..3).map(move |c| (p, c)))
                .map(|(p, c)| f(p, c))
                .sum::<f64>()
        };
        Summary {
            mean_abs_bias: sum(&|p, c| b(p, c).abs()) / k,
            mean_bias: sum(&|p, c| b(p, c)) / k,
            mean_bias_se: (sum(&|p, c| self.variance[p][c] / self.count[p].max(1) as f64)).sqrt()
                / k,
            mean_std: sum(&|p, c| self.variance[p][c].sqrt()) / k,
            rmse: (sum(&|p, c| b(p, c).powi(2) + self.variance[p][c]) / k).sqrt(),
            ms_per_frame: self.seconds * 1000.0 / self.runs.max(1) as f64,
            lookups_per_pixel: self.lookups as f64
                / (self.mean.len().max(1) as f64 * self.runs.max(1) as f64),
            runs: self.runs,
            pixels: idx.len(),
        }
    }
}

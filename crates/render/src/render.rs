//! The progressive render loop: one pass adds sample index `s` to every
//! pixel, rows in parallel. Each pixel's random streams depend only on
//! (seed, pixel, sample index), and each pixel accumulates its samples in
//! index order, so the image is bit-identical for any thread count or
//! scheduling.

use crate::integrators::IntegratorKind;
use crate::scene::Scene;
use crate::shard::Piece;
use crate::world::film::{Accumulated, Film};
use fogbank_math::SampleKey;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Passes to render (the last may stop early on cancel).
    pub spp: u32,
    pub seed: u32,
    /// Stop starting new passes after this long.
    pub time_budget: Option<Duration>,
}

/// Shared between the render loop and whoever watches it (progress bar,
/// Ctrl-C handler).
#[derive(Default)]
pub struct Progress {
    /// Pixel samples finished so far.
    pub samples_done: AtomicU64,
    /// Passes fully finished.
    pub passes_done: AtomicU64,
    /// Set to stop: rows not yet started are skipped, the film keeps what
    /// was accumulated.
    pub cancel: AtomicBool,
}

#[derive(Clone, Debug)]
pub struct RenderResult {
    pub film: Film,
    pub seconds: f64,
    pub interrupted: bool,
}

#[derive(Default)]
struct RowTotals {
    lookups: u64,
    nan: u64,
    inf: u64,
}

impl RowTotals {
    #[inline]
    fn count(&mut self, a: Accumulated) {
        match a {
            Accumulated::Added => {}
            Accumulated::Nan => self.nan += 1,
            Accumulated::Inf => self.inf += 1,
        }
    }
}

/// Renders in the current rayon pool (callers size it with `--threads`).
pub fn render(scene: &Scene, opts: &RenderOptions, progress: &Progress) -> RenderResult {
    render_observed(scene, opts, progress, &mut |_, _| {})
}

/// [`render`], calling `after_pass(film, seconds)` after every complete pass
/// with the render time so far. Time spent in the callback is not counted,
/// so equal-time measurements can inspect the film without skewing them.
pub fn render_observed(
    scene: &Scene,
    opts: &RenderOptions,
    progress: &Progress,
    after_pass: &mut dyn FnMut(&Film, f64),
) -> RenderResult {
    render_piece(scene, opts, &Piece::whole(opts.spp), progress, after_pass)
}

/// [`render_observed`] of one piece of the work (a shard): its sample
/// indices of its pixels, each exactly as the whole render would compute
/// them. Frame-based integrators (`restir`) carry state from pass to pass
/// and pixel to pixel, so they take whole renders only.
pub fn render_piece(
    scene: &Scene,
    opts: &RenderOptions,
    piece: &Piece,
    progress: &Progress,
    after_pass: &mut dyn FnMut(&Film, f64),
) -> RenderResult {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut film = Film::new(w, h);
    scene.integrator.prepare(&scene.world);
    let mut start = Instant::now();
    let mut interrupted = false;
    let frame_based = matches!(scene.integrator, IntegratorKind::Restir(_));
    assert!(
        !frame_based || *piece == Piece::whole(opts.spp),
        "restir renders whole images only"
    );
    for pass in piece.sample_range() {
        if progress.cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        if let Some(b) = opts.time_budget {
            if start.elapsed() >= b {
                break;
            }
        }
        let totals = match &scene.integrator {
            IntegratorKind::Restir(r) => {
                match r.last_frame(&scene.world, opts.seed, pass, &progress.cancel) {
                    Some(f) => {
                        let t = add_frame(&mut film, &f.radiance);
                        progress
                            .samples_done
                            .fetch_add(f.radiance.len() as u64, Ordering::Relaxed);
                        RowTotals {
                            lookups: f.lookups,
                            ..t
                        }
                    }
                    None => RowTotals::default(),
                }
            }
            _ => pixel_pass(scene, opts.seed, pass, piece, &mut film, progress),
        };
        film.lookups += totals.lookups;
        film.nan_samples += totals.nan;
        film.inf_samples += totals.inf;
        if progress.cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        progress.passes_done.fetch_add(1, Ordering::Relaxed);
        let observing = Instant::now();
        after_pass(&film, (observing - start).as_secs_f64());
        start += observing.elapsed();
    }
    RenderResult {
        film,
        seconds: start.elapsed().as_secs_f64(),
        interrupted,
    }
}

/// One pass of a per-pixel integrator: sample index `pass` of every pixel.
fn pixel_pass(
    scene: &Scene,
    seed: u32,
    pass: u32,
    piece: &Piece,
    film: &mut Film,
    progress: &Progress,
) -> RowTotals {
    let w = film.width;
    film.sums
        .par_chunks_mut(w as usize)
        .zip(film.count.par_chunks_mut(w as usize))
        .enumerate()
        .map(|(y, (sums, count))| {
            let mut t = RowTotals::default();
            if progress.cancel.load(Ordering::Relaxed) {
                return t;
            }
            let mut done = 0;
            for x in 0..w as usize {
                if !piece.has_pixel(x as u32, y as u32, w) {
                    continue;
                }
                done += 1;
                let key = SampleKey {
                    seed,
                    pixel: (y * w as usize + x) as u32,
                    sample: pass,
                    dimension: 0,
                };
                let s = scene.sample_pixel(x as u32, y as u32, key);
                t.lookups += s.lookups as u64;
                t.count(sums[x].add(&mut count[x], s.radiance));
            }
            progress.samples_done.fetch_add(done, Ordering::Relaxed);
            t
        })
        .reduce(
            || RowTotals {
                lookups: 0,
                nan: 0,
                inf: 0,
            },
            |a, b| RowTotals {
                lookups: a.lookups + b.lookups,
                nan: a.nan + b.nan,
                inf: a.inf + b.inf,
            },
        )
}

/// Adds one sample per pixel (a frame of a frame-based integrator).
fn add_frame(film: &mut Film, radiance: &[fogbank_math::Vec3]) -> RowTotals {
    let mut t = RowTotals::default();
    for (i, l) in radiance.iter().enumerate() {
        t.count(film.sums[i].add(&mut film.count[i], *l));
    }
    t
}

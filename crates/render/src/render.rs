//! The progressive render loop: one pass adds sample index `s` to every
//! pixel, rows in parallel. Each pixel's random streams depend only on
//! (seed, pixel, sample index), and each pixel accumulates its samples in
//! index order, so the image is bit-identical for any thread count or
//! scheduling.

use crate::integrators::restir::Restir;
use crate::integrators::shared::PixelSample;
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

impl RenderOptions {
    /// `spp` passes from `seed`, without a time budget.
    pub fn new(spp: u32, seed: u32) -> RenderOptions {
        RenderOptions {
            spp,
            seed,
            time_budget: None,
        }
    }
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
    render_piece(scene, opts, &Piece::whole(opts.spp), progress)
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
    render_passes(
        scene,
        opts,
        &Piece::whole(opts.spp),
        progress,
        Some(after_pass),
    )
}

/// [`render`] of one piece of the work (a shard): its sample indices of
/// its pixels, each exactly as the whole render would compute them.
/// Frame-based integrators (`restir`) carry state from pass to pass and
/// pixel to pixel, so they take whole renders only.
pub fn render_piece(
    scene: &Scene,
    opts: &RenderOptions,
    piece: &Piece,
    progress: &Progress,
) -> RenderResult {
    render_passes(scene, opts, piece, progress, None)
}

/// [`render_piece`], calling `after_pass(film, seconds)` after every
/// complete pass when given (as [`render_observed`]).
pub fn render_piece_observed(
    scene: &Scene,
    opts: &RenderOptions,
    piece: &Piece,
    progress: &Progress,
    after_pass: Option<&mut AfterPass>,
) -> RenderResult {
    render_passes(scene, opts, piece, progress, after_pass)
}

/// What `render_observed` calls after each pass: (film, seconds so far).
pub type AfterPass<'a> = dyn FnMut(&Film, f64) + 'a;

/// Passes per batch are chosen so that a batch takes about this long.
const BATCH_SECONDS: f64 = 0.05;
const MAX_BATCH: u32 = 64;

/// The render loop. Unobserved, without a time budget, per-pixel integrators
/// render batches of passes (each row takes several sample indices before
/// the threads join), so short passes do not pay a fork/join each; the
/// film's exact sums make the image the same for any batching.
fn render_passes(
    scene: &Scene,
    opts: &RenderOptions,
    piece: &Piece,
    progress: &Progress,
    mut after_pass: Option<&mut AfterPass>,
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
    // The pin stream changes the grids from pass to pass: one pass a batch.
    let mut pin_stream = match &scene.integrator {
        IntegratorKind::VolPath(v) => v.pin_stream(&scene.world),
        _ => None,
    };
    let batching =
        after_pass.is_none() && opts.time_budget.is_none() && !frame_based && pin_stream.is_none();
    let (mut pass, end) = (piece.samples[0], piece.samples[1]);
    let mut batch = 1;
    while pass < end {
        if progress.cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        if let Some(b) = opts.time_budget {
            if start.elapsed() >= b {
                break;
            }
        }
        let n = batch.min(end - pass);
        let clock = Instant::now();
        let totals = match &scene.integrator {
            IntegratorKind::Restir(r) => {
                restir_pass(r, scene, opts.seed, pass, &mut film, progress)
            }
            integrator => {
                let world = &scene.world;
                let streamed = pin_stream.as_mut().map(|p| p.at(world, pass).clone());
                let sample = |x, y, key| match (integrator, &streamed) {
                    (IntegratorKind::VolPath(v), Some(set)) => {
                        v.sample_with(world, x, y, key, Some(set))
                    }
                    _ => integrator.sample_pixel(world, x, y, key),
                };
                let passes = pass..pass + n;
                pixel_passes(&sample, opts.seed, passes, piece, &mut film, progress)
            }
        };
        film.lookups += totals.lookups;
        film.nan_samples += totals.nan;
        film.inf_samples += totals.inf;
        if progress.cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        progress.passes_done.fetch_add(n as u64, Ordering::Relaxed);
        pass += n;
        if batching {
            let per_pass = clock.elapsed().as_secs_f64() / n as f64;
            batch = ((BATCH_SECONDS / per_pass.max(1e-9)) as u32).clamp(1, MAX_BATCH);
        }
        if let Some(f) = after_pass.as_mut() {
            let observing = Instant::now();
            f(&film, (observing - start).as_secs_f64());
            start += observing.elapsed();
        }
    }
    RenderResult {
        film,
        seconds: start.elapsed().as_secs_f64(),
        interrupted,
    }
}

/// Sample index `pass` of a frame-based integrator: ReSTIR's last frame
/// of the sequence for that index, added to the film.
fn restir_pass(
    r: &Restir,
    scene: &Scene,
    seed: u32,
    pass: u32,
    film: &mut Film,
    progress: &Progress,
) -> RowTotals {
    match r.last_frame(&scene.world, seed, pass, &progress.cancel) {
        Some(f) => {
            let t = add_frame(film, &f.radiance);
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

/// Passes of a per-pixel integrator: sample indices `passes` of every
/// pixel of the piece (`sample(x, y, key)`), each row taking all of them
/// before the next join.
fn pixel_passes<S>(
    sample_at: &S,
    seed: u32,
    passes: std::ops::Range<u32>,
    piece: &Piece,
    film: &mut Film,
    progress: &Progress,
) -> RowTotals
where
    S: Fn(u32, u32, SampleKey) -> PixelSample + Sync,
{
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
                for sample in passes.clone() {
                    let key = SampleKey {
                        seed,
                        pixel: (y * w as usize + x) as u32,
                        sample,
                        dimension: 0,
                    };
                    let s = sample_at(x as u32, y as u32, key);
                    t.lookups += s.lookups as u64;
                    t.count(sums[x].add(&mut count[x], s.radiance));
                }
                done += passes.len() as u64;
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

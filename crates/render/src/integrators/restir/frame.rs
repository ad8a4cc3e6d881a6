//! One frame of volumetric ReSTIR (Lin et al. 2021 §5, Fig. 5): candidates →
//! temporal reuse → spatial reuse → final shading, each a pass over every
//! pixel (rows in parallel; each pixel's random numbers are keyed by seed,
//! pixel, sequence, frame and pass, so a frame does not depend on the
//! thread count). The post-spatial reservoirs go to the next frame (§2.5).
//! Primary rays go through pixel centres in every pass (the authors' code):
//! reuse compares targets of fixed pixel rays.

use super::integrator::{pixel_ray, FrameData, Restir};
use super::path::PathSample;
use super::primary::PrimaryT;
use super::reservoir::Reservoir;
use super::temporal::Previous;
use crate::world::World;
use fogbank_math::{Pcg32, SampleKey, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Random-stream dimensions of a frame's passes (after the integrators'
/// camera and estimator streams).
const DIM_BASE: u32 = 2;
const PASSES: u32 = 4;

/// Seconds spent in each pass of a frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct PassTimes {
    pub candidates: f64,
    pub temporal: f64,
    pub spatial: f64,
    pub shading: f64,
}

pub struct FrameOutput {
    pub radiance: Vec<Vec3>,
    pub lookups: u64,
    pub times: PassTimes,
}

/// A sequence of frames: what one frame leaves the next.
pub struct Sequence<'r> {
    restir: &'r Restir,
    seed: u32,
    sequence: u32,
    frame: u32,
    prev: Option<Vec<Reservoir<PathSample>>>,
    /// The previous frame's primary-ray T̃ tables.
    prev_primary: Option<PrimaryT>,
}

impl<'r> Sequence<'r> {
    /// Sequence `sequence` (independent sequences have independent random
    /// numbers) of the scene rendered with `seed`.
    pub fn new(restir: &'r Restir, seed: u32, sequence: u32) -> Self {
        Sequence {
            restir,
            seed,
            sequence,
            frame: 0,
            prev: None,
            prev_primary: None,
        }
    }

    /// Renders the next frame with the current frame's data `cur` and the
    /// previous frame's `prev` (the same for a static scene). The restir
    /// parameters are the sequence's; the mips and lights are each frame's.
    pub fn frame(&mut self, cur: &FrameData, prev: &FrameData) -> FrameOutput {
        let r = self.restir;
        // This frame's primary-ray T̃ tables; the previous frame's came with it.
        // A frame of a still scene (`prev` is `cur`, as in a static
        // render) has the previous frame's tables: same camera, same mip.
        let still = std::ptr::eq(cur.world, prev.world) && std::ptr::eq(cur.mips, prev.mips);
        let reused = still && self.prev_primary.is_some();
        let full = &cur.world.media[0].medium;
        let reuse = cur.mips.reuse(full, r.params.reuse_mip);
        let clock = Instant::now();
        let built = (r.params.primary_table && !reused)
            .then(|| PrimaryT::build(reuse, r.params.reuse_step, &cur.world.camera))
            .flatten();
        let table_seconds = clock.elapsed().as_secs_f64();
        let cur = &FrameData {
            primary: if reused {
                self.prev_primary.as_ref()
            } else {
                built.as_ref()
            },
            ..*cur
        };
        let prev = &FrameData {
            primary: self.prev_primary.as_ref(),
            ..*prev
        };
        let cam = &cur.world.camera;
        let (w, n) = (cam.width, (cam.width * cam.height) as usize);
        let (seed, sequence, frame) = (self.seed, self.sequence, self.frame);
        let rng = move |pixel: usize, pass: u32| {
            SampleKey {
                seed,
                pixel: pixel as u32,
                sample: sequence,
                dimension: DIM_BASE + PASSES * frame + pass,
            }
            .rng()
        };
        let pixel = |i: usize| ((i as u32) % w, (i as u32) / w);
        let ray = |i: usize| pixel_ray(cur.world, pixel(i));
        let mut times = PassTimes::default();
        let mut lookups = 0u64;

        let clock = Instant::now();
        let (res, l) = collect(n, |i, lk| {
            r.candidates(cur, Some(i), &ray(i), &mut rng(i, 0), lk)
        });
        lookups += l;
        // The tables serve every pass; their time is counted here.
        times.candidates = table_seconds + clock.elapsed().as_secs_f64();

        let (res, l) = self.reuse(cur, prev, res, &rng, &mut times);
        lookups += l;

        let clock = Instant::now();
        let (radiance, lk): (Vec<Vec3>, Vec<u32>) = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut lk = 0;
                let l = r.shade(cur, &ray(i), &res[i], &mut rng(i, 3), &mut lk);
                (l, lk)
            })
            .unzip();
        times.shading = clock.elapsed().as_secs_f64();
        lookups += lk.iter().map(|&l| l as u64).sum::<u64>();

        self.prev = Some(res);
        if !reused {
            self.prev_primary = built;
        }
        self.frame += 1;
        FrameOutput {
            radiance,
            lookups,
            times,
        }
    }

    /// Temporal reuse (when the previous frame has the image's size) and
    /// spatial reuse of the candidate reservoirs `res` (Lin et al. 2021 §4.2–4.3);
    /// `rng(pixel, pass)` gives each pass its stream.
    fn reuse(
        &self,
        cur: &FrameData,
        prev: &FrameData,
        mut res: Vec<Reservoir<PathSample>>,
        rng: &(impl Fn(usize, u32) -> Pcg32 + Sync),
        times: &mut PassTimes,
    ) -> (Vec<Reservoir<PathSample>>, u64) {
        let r = self.restir;
        let cam = &cur.world.camera;
        let (w, n) = (cam.width, (cam.width * cam.height) as usize);
        let pixel = |i: usize| ((i as u32) % w, (i as u32) / w);
        let mut lookups = 0u64;
        let old_cam = &prev.world.camera;
        let same_size = old_cam.width == cam.width && old_cam.height == cam.height;
        if let (true, Some(old)) = (r.params.reuse.temporal, &self.prev) {
            if same_size {
                let clock = Instant::now();
                let before = Previous {
                    reservoirs: old,
                    data: prev,
                };
                let (t, l) = collect(n, |i, lk| {
                    r.temporal(cur, &before, pixel(i), res[i], &mut rng(i, 1), lk)
                });
                res = t;
                lookups += l;
                times.temporal = clock.elapsed().as_secs_f64();
            }
        }
        if r.params.reuse.spatial {
            let clock = Instant::now();
            let (s, l) = collect(n, |i, lk| {
                r.spatial(cur, &res, pixel(i), self.frame, &mut rng(i, 2), lk)
            });
            res = s;
            lookups += l;
            times.spatial = clock.elapsed().as_secs_f64();
        }

        (res, lookups)
    }
}

/// Runs `f(pixel, &mut lookups)` for every pixel in parallel.
fn collect<F>(n: usize, f: F) -> (Vec<Reservoir<PathSample>>, u64)
where
    F: Fn(usize, &mut u32) -> Reservoir<PathSample> + Sync,
{
    // Unzipped in parallel: a serial copy of the reservoirs would cost
    // thread scaling.
    let (v, lk): (Vec<_>, Vec<u32>) = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut lk = 0;
            (f(i, &mut lk), lk)
        })
        .unzip();
    (v, lk.iter().map(|&l| l as u64).sum())
}

impl Restir {
    /// The last frame of sequence `sequence` of the static scene (`frames`
    /// frames); `None` when `cancel` is set between frames.
    pub fn last_frame(
        &self,
        world: &World,
        seed: u32,
        sequence: u32,
        cancel: &AtomicBool,
    ) -> Option<FrameOutput> {
        let data = self.data(world);
        let mut seq = Sequence::new(self, seed, sequence);
        let mut out = None;
        let mut lookups = 0;
        for _ in 0..self.params.frames {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let f = seq.frame(&data, &data);
            lookups += f.lookups;
            out = Some(f);
        }
        out.map(|mut f| {
            f.lookups = lookups;
            f
        })
    }
}

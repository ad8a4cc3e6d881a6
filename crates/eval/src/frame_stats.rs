//! Per-pixel statistics of an estimator over K independent 1-spp frames of
//! the transmittance view (seed 000 §6.1, Figs. 8–10): mean, single-frame
//! standard deviation, and bias against an exact reference.
//!
//! Rays go through pixel centres so that the reference is one exact value
//! per pixel; frame k uses sample index k of the pixel's estimator stream.
//! Each pixel runs its K frames in a row with Welford's update, so memory is
//! independent of K and the result is independent of the thread count.

use fogbank_estimators::Estimator;
use fogbank_math::SampleKey;
use fogbank_render::integrators::{dim, transmittance::along_ray};
use fogbank_render::Scene;
use rayon::prelude::*;
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct FrameStats {
    pub width: u32,
    pub height: u32,
    pub runs: u32,
    /// Per-pixel mean transmittance over the runs.
    pub mean: Vec<f64>,
    /// Per-pixel variance of a single frame (unbiased, n − 1).
    pub variance: Vec<f64>,
    /// Per-pixel exact transmittance, when a reference estimator was given.
    pub reference: Option<Vec<f64>>,
    pub lookups: u64,
    pub seconds: f64,
}

/// Image-level figures. With a reference, averages run over the pixels
/// whose exact transmittance is below 1 (those the media cover), so empty
/// background does not dilute them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    pub mean_abs_bias: f64,
    pub mean_bias: f64,
    pub mean_std: f64,
    pub rmse: f64,
    pub ms_per_frame: f64,
    pub lookups_per_pixel: f64,
    pub runs: u32,
    pub pixels: usize,
}

/// Runs `runs` frames of `estimator` (and one frame of `reference`, which
/// must be deterministic, e.g. `analytic_trilinear`).
pub fn transmittance_stats(
    scene: &Scene,
    estimator: Estimator,
    reference: Option<Estimator>,
    runs: u32,
    seed: u32,
) -> FrameStats {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let ray_of = |p: usize| {
        scene
            .camera
            .ray((p % w as usize) as f32 + 0.5, (p / w as usize) as f32 + 0.5)
    };
    let start = Instant::now();
    let per_pixel: Vec<(f64, f64, u64)> = (0..(w * h) as usize)
        .into_par_iter()
        .map(|p| {
            let ray = ray_of(p);
            let (mut mean, mut m2, mut lookups) = (0.0f64, 0.0f64, 0u64);
            for k in 0..runs {
                let mut rng = SampleKey {
                    seed,
                    pixel: p as u32,
                    sample: k,
                    dimension: dim::ESTIMATOR,
                }
                .rng();
                let e = along_ray(scene, estimator, &ray, &mut rng);
                lookups += e.lookups as u64;
                let x = e.transmittance as f64;
                let d = x - mean;
                mean += d / (k + 1) as f64;
                m2 += d * (x - mean);
            }
            (
                mean,
                if runs > 1 {
                    m2 / (runs - 1) as f64
                } else {
                    0.0
                },
                lookups,
            )
        })
        .collect();
    let seconds = start.elapsed().as_secs_f64();
    let reference = reference.map(|r| {
        (0..(w * h) as usize)
            .into_par_iter()
            .map(|p| {
                let mut rng = SampleKey {
                    seed,
                    pixel: p as u32,
                    sample: 0,
                    dimension: dim::ESTIMATOR,
                }
                .rng();
                along_ray(scene, r, &ray_of(p), &mut rng).transmittance as f64
            })
            .collect()
    });
    FrameStats {
        width: w,
        height: h,
        runs,
        mean: per_pixel.iter().map(|v| v.0).collect(),
        variance: per_pixel.iter().map(|v| v.1).collect(),
        reference,
        lookups: per_pixel.iter().map(|v| v.2).sum(),
        seconds,
    }
}

impl FrameStats {
    pub fn summary(&self) -> Summary {
        let n = self.mean.len();
        let covered: Vec<usize> = match &self.reference {
            Some(r) => (0..n).filter(|&p| r[p] < 1.0 - 1e-6).collect(),
            None => (0..n).collect(),
        };
        let k = covered.len().max(1) as f64;
        let bias = |p: usize| self.reference.as_ref().map_or(0.0, |r| self.mean[p] - r[p]);
        Summary {
            mean_abs_bias: covered.iter().map(|&p| bias(p).abs()).sum::<f64>() / k,
            mean_bias: covered.iter().map(|&p| bias(p)).sum::<f64>() / k,
            mean_std: covered
                .iter()
                .map(|&p| self.variance[p].sqrt())
                .sum::<f64>()
                / k,
            rmse: (covered
                .iter()
                .map(|&p| bias(p).powi(2) + self.variance[p])
                .sum::<f64>()
                / k)
                .sqrt(),
            ms_per_frame: self.seconds * 1000.0 / self.runs.max(1) as f64,
            lookups_per_pixel: self.lookups as f64 / (n as f64 * self.runs.max(1) as f64),
            runs: self.runs,
            pixels: covered.len(),
        }
    }
}

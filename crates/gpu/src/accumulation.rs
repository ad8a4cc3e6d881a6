//! Bind group 1 of every kernel: the frame uniform (`Frame` in
//! `wgsl/frame.wgsl`: camera, image, seed, estimator and integrator
//! options) and the accumulation buffers (running mean with the sample
//! count, M2 with the dropped samples, lookups; the chunk slots a dispatch
//! merges from), read back as a film.

use crate::context::buffer_entry;
use crate::{Gpu, GpuError};
use bytemuck::{Pod, Zeroable};
use fogbank_render::Film;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct Frame {
    pub(crate) cam_origin: [f32; 4],
    pub(crate) cam_forward: [f32; 4],
    pub(crate) cam_right: [f32; 4],
    pub(crate) cam_up: [f32; 4],
    pub(crate) background: [f32; 4],
    pub(crate) tan_half: [f32; 2],
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) seed: u32,
    pub(crate) first_sample: u32,
    pub(crate) sample_count: u32,
    pub(crate) media_count: u32,
    pub(crate) pixel_jitter: u32,
    pub(crate) est_samples: u32,
    pub(crate) est_step: f32,
    pub(crate) est_flags: u32,
    pub(crate) max_depth: u32,
    pub(crate) rr_depth: u32,
    pub(crate) mis_samples: u32,
    pub(crate) march_step: f32,
    pub(crate) pin_mask_iterations: u32,
    /// First image row of this dispatch (kernels with per-invocation
    /// scratch render in bands of rows; 0 otherwise).
    pub(crate) tile_y: u32,
    /// Chunks of [`SAMPLES_PER_CHUNK`] samples this dispatch runs side by
    /// side (the z dimension of the grid).
    pub(crate) chunks: u32,
    /// Pixels of this dispatch's band (width × its rows).
    pub(crate) band_pixels: u32,
    /// Ratio and residual ratio tracking's roulette threshold (0: off).
    pub(crate) est_roulette: f32,
    pub(crate) pad: [u32; 3],
}

pub use crate::contract::SAMPLES_PER_CHUNK;

impl Frame {
    /// The camera, image and media count of `scene` with the transmittance
    /// estimator's options `est`; every integrator option 0 (kernels set
    /// theirs with struct-update syntax).
    pub(crate) fn of_scene(
        scene: &fogbank_render::Scene,
        est: &crate::contract::GpuEstimator,
    ) -> Frame {
        let (origin, forward, right, up, tan_half) = scene.camera.basis();
        let v4 = |v: glam::Vec3| [v.x, v.y, v.z, 0.0];
        let (near, far) = scene.camera.clip();
        Frame {
            // The clip planes ride in the w components (frame.wgsl).
            cam_origin: [origin.x, origin.y, origin.z, near],
            cam_forward: [forward.x, forward.y, forward.z, far],
            cam_right: v4(right),
            cam_up: v4(up),
            background: [0.0; 4],
            tan_half,
            width: scene.camera.width,
            height: scene.camera.height,
            seed: 0,
            first_sample: 0,
            sample_count: 0,
            media_count: scene.media.len() as u32,
            pixel_jitter: 0,
            est_samples: est.samples,
            est_step: est.step,
            est_flags: est.flags,
            max_depth: 0,
            rr_depth: 0,
            mis_samples: 0,
            march_step: 0.0,
            pin_mask_iterations: 0,
            tile_y: 0,
            chunks: 1,
            band_pixels: 0,
            est_roulette: est.roulette,
            pad: [0; 3],
        }
    }
}

/// Bind group 1 of every kernel: the frame uniform, the accumulation
/// buffers (mean radiance and count, M2 and dropped samples, lookups) and
/// the chunk slots of a dispatch.
pub(crate) fn frame_bind_group_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    use wgpu::BufferBindingType::{Storage, Uniform};
    let storage_rw = |binding| buffer_entry(binding, Storage { read_only: false });
    gpu.bind_group_layout(
        "frame",
        &[
            buffer_entry(0, Uniform),
            storage_rw(1),
            storage_rw(2),
            storage_rw(3),
        ],
    )
}

/// After `n` passes over `pixels` pixels: the progress counted and, with
/// an observer, the film so far shown with the render seconds so far; the
/// read-back is not counted (`start` moves past it).
pub(crate) fn after_passes(
    progress: &fogbank_render::Progress,
    n: u32,
    pixels: u64,
    after: &mut Option<Observer<'_>>,
    start: &mut std::time::Instant,
    film: impl FnOnce() -> Result<Film, GpuError>,
) -> Result<(), GpuError> {
    use std::sync::atomic::Ordering;
    progress
        .samples_done
        .fetch_add(n as u64 * pixels, Ordering::Relaxed);
    progress.passes_done.fetch_add(n as u64, Ordering::Relaxed);
    if let Some(f) = after.as_mut() {
        let observing = std::time::Instant::now();
        f(&film()?, (observing - *start).as_secs_f64());
        *start += observing.elapsed();
    }
    Ok(())
}

/// Called with the film so far and the render seconds so far.
pub type Observer<'a> = &'a mut dyn FnMut(&Film, f64);

pub struct GpuRender {
    pub film: Film,
    /// Wall-clock seconds of the render loop (upload excluded).
    pub seconds: f64,
    /// Kernel time from timestamp queries, when the device has them.
    pub gpu_ms: Option<f64>,
    pub interrupted: bool,
    pub upload_bytes: u64,
    /// Command buffers submitted to the queue.
    pub submits: u32,
}

/// The device accumulation buffers as a film (sums widened to f64).
pub(crate) fn read_film(
    gpu: &Gpu,
    w: u32,
    h: u32,
    moments: &wgpu::Buffer,
    lookups: &wgpu::Buffer,
) -> Result<Film, GpuError> {
    let pixels = w as u64 * h as u64;
    let raw = gpu.read_back(moments)?;
    // Pixel i: (mean, n) at 2i, (M2, dropped) at 2i + 1.
    let both: &[[[f32; 4]; 2]] = bytemuck::cast_slice(&raw);
    let looks: Vec<u32> = bytemuck::cast_slice(&gpu.read_back(lookups)?).to_vec();
    let mut film = Film::new(w, h);
    for i in 0..pixels as usize {
        // The device keeps the mean and M2 (frame.wgsl); the film keeps
        // Σx and Σx², here in f64, where the conversion loses nothing a
        // variance needs.
        let n = both[i][0][3] as f64;
        film.set_moments(
            i,
            [0, 1, 2].map(|c| both[i][0][c] as f64 * n),
            [0, 1, 2].map(|c| {
                let mean = both[i][0][c] as f64;
                both[i][1][c] as f64 + n * mean * mean
            }),
            both[i][0][3] as u32,
        );
        film.nan_samples += both[i][1][3] as u64;
        film.lookups += looks[i] as u64;
    }
    Ok(film)
}

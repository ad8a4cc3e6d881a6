//! The progressive render loop on the GPU for the integrators with a WGSL
//! kernel (`transmittance`, `direct`, `volpath`, `point_mis`, `visopt`,
//! `ament`): the same image as the
//! CPU's (same scene, seed, sample indices and random streams), accumulated
//! on the device and read back once.

use crate::accumulation::{after_passes, frame_bind_group_layout, read_film, Frame};
pub use crate::accumulation::{GpuRender, Observer};
use crate::contract::{gpu_estimator, pin_mode_id, sampler_id, strategy_id, GpuEstimator};
use crate::pins::PinBuffers;
use crate::scene_buffers::SceneBuffers;
use crate::shaders;
use crate::visopt::{importance_fields, VisOptBuffers};
use crate::{Gpu, GpuError};
use fogbank_render::integrators::shared::pin_params::{PinMode, PinParams, Tracking};
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{Progress, RenderOptions, Scene};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// What the integrator asks of the kernels.
pub(crate) struct Kernel {
    source: KernelSource,
    /// Needs bind group 2 (lights, environment, shading).
    scatter: bool,
    /// The transmittance estimator's `EST_*` id and frame options.
    pub(crate) est: GpuEstimator,
    background: glam::Vec3,
    max_depth: u32,
    rr_depth: u32,
    /// `SAMPLER_*` id, or for `point_mis` the `STRATEGY_*` id.
    pub(crate) sampler: u32,
    mis_samples: u32,
    /// `INTEGRATOR_*` bits.
    flags: u32,
    /// `volpath`'s seed 004 keys (`pins`, `tracking`, `march_step`,
    /// `pin_grid`); the default is plain `volpath`.
    pins: PinParams,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum KernelSource {
    Transmittance,
    Scatter,
    PointMis,
    /// Seed 003: `visopt` and `ament`, group 3 their [`VisOptBuffers`].
    VisOpt,
    Ament,
}

impl Kernel {
    pub(crate) fn of(scene: &Scene) -> Result<Kernel, GpuError> {
        if let IntegratorKind::Restir(_) = scene.integrator {
            return Err(no_restir());
        }
        let estimator = scene.integrator.estimator();
        let est = gpu_estimator(estimator).ok_or_else(|| {
            GpuError(format!(
                "estimator `{}` has no GPU kernel",
                estimator.name()
            ))
        })?;
        let k = match &scene.integrator {
            IntegratorKind::Transmittance { background, .. } => Kernel {
                source: KernelSource::Transmittance,
                mis_samples: 0,
                flags: 0,
                scatter: false,
                est,
                background: *background,
                max_depth: 0,
                rr_depth: 0,
                sampler: 0,
                pins: PinParams::default(),
            },
            IntegratorKind::Direct(d) => Kernel {
                source: KernelSource::Scatter,
                mis_samples: 0,
                flags: 0,
                scatter: true,
                est,
                background: glam::Vec3::ZERO,
                max_depth: 1,
                rr_depth: u32::MAX,
                sampler: sampler_id(d.distance),
                pins: PinParams::default(),
            },
            IntegratorKind::VolPath(v) => Kernel {
                source: KernelSource::Scatter,
                mis_samples: 0,
                flags: volpath_flags(v),
                scatter: true,
                est,
                background: glam::Vec3::ZERO,
                max_depth: v.max_depth,
                rr_depth: v.rr_depth,
                sampler: sampler_id(v.distance),
                pins: v.pins.clone(),
            },
            IntegratorKind::PointMis(p) => Kernel {
                source: KernelSource::PointMis,
                scatter: true,
                est,
                background: glam::Vec3::ZERO,
                max_depth: 1,
                rr_depth: u32::MAX,
                sampler: strategy_id(p.strategy),
                mis_samples: p.mis_samples,
                flags: 0,
                pins: PinParams::default(),
            },
            IntegratorKind::Restir(_) => return Err(no_restir()),
            IntegratorKind::VisOpt(_) | IntegratorKind::Ament(_) => Kernel {
                source: if let IntegratorKind::Ament(_) = scene.integrator {
                    KernelSource::Ament
                } else {
                    KernelSource::VisOpt
                },
                scatter: true,
                est,
                background: glam::Vec3::ZERO,
                max_depth: 1,
                rr_depth: u32::MAX,
                sampler: 0,
                mis_samples: 0,
                flags: 0,
                pins: PinParams::default(),
            },
        };
        Ok(k)
    }
}

/// `INTEGRATOR_*` bits of a `volpath`.
fn volpath_flags(v: &fogbank_render::integrators::volpath::VolPath) -> u32 {
    use crate::contract::{INTEGRATOR_LIGHT_ONLY, INTEGRATOR_RAY_MARCHING, INTEGRATOR_UNQUANTISED};
    let mut f = 0;
    if v.light_only {
        f |= INTEGRATOR_LIGHT_ONLY;
    }
    if v.pins.tracking() == Tracking::RayMarching {
        f |= INTEGRATOR_RAY_MARCHING;
    }
    if v.pins.grid.unquantised {
        f |= INTEGRATOR_UNQUANTISED;
    }
    f
}

fn no_restir() -> GpuError {
    GpuError(
        "integrator `restir` runs its own passes (crate::restir), not a per-sample kernel".into(),
    )
}

/// Samples per pixel per dispatch: short dispatches keep the desktop
/// responsive and cancellation prompt.
const SAMPLES_PER_DISPATCH: u32 = 4;
const MAX_TIMED_DISPATCHES: u32 = 2048;

pub fn render(
    gpu: &Gpu,
    scene: &Scene,
    opts: &RenderOptions,
    progress: &Progress,
) -> Result<GpuRender, GpuError> {
    render_observed(gpu, scene, opts, progress, None)
}

/// [`render`], calling `after(film, seconds)` after every dispatch with the
/// film read back and the render time so far (the read-back is not
/// counted), for equal-time convergence curves.
pub fn render_observed(
    gpu: &Gpu,
    scene: &Scene,
    opts: &RenderOptions,
    progress: &Progress,
    after: Option<Observer<'_>>,
) -> Result<GpuRender, GpuError> {
    if let IntegratorKind::Restir(_) = scene.integrator {
        return crate::restir::render(gpu, scene, opts, progress, after);
    }
    render_kernel(gpu, scene, &Kernel::of(scene)?, opts, progress, after)
}

/// Runs `kernel` (as [`Kernel::of`] the scene's integrator gives it).
pub(crate) fn render_kernel(
    gpu: &Gpu,
    scene: &Scene,
    kernel: &Kernel,
    opts: &RenderOptions,
    progress: &Progress,
    mut after: Option<Observer<'_>>,
) -> Result<GpuRender, GpuError> {
    let est = &kernel.est;
    let seed003 = matches!(kernel.source, KernelSource::VisOpt | KernelSource::Ament);
    let fields = if seed003 {
        importance_fields(scene)
    } else {
        Vec::new()
    };
    let media = SceneBuffers::upload_with(gpu, scene, &[], &fields)?;
    let device = &gpu.device;
    let lights = if kernel.scatter {
        Some(crate::lights::LightBuffers::upload(
            gpu,
            scene,
            &media.properties,
        )?)
    } else {
        None
    };
    // Group 3 of the scatter kernel: the pin grids, gathered on the device.
    let pins = if kernel.source == KernelSource::Scatter {
        let on = kernel.pins.mode != PinMode::Off;
        Some(PinBuffers::build(
            gpu,
            scene,
            &media,
            on.then_some(&kernel.pins),
        )?)
    } else {
        None
    };
    let visopt = if seed003 {
        Some(VisOptBuffers::build(gpu, scene, &media.field_first)?)
    } else {
        None
    };
    // Group 3: the pin grids or seed 003's data.
    let group3 = match (&pins, &visopt) {
        (Some(p), _) => Some((&p.layout, &p.bind_group)),
        (_, Some(v)) => Some((&v.layout, &v.bind_group)),
        _ => None,
    };
    let source = match kernel.source {
        KernelSource::Transmittance => shaders::transmittance_kernel(),
        KernelSource::Scatter => shaders::scatter_kernel(),
        KernelSource::PointMis => shaders::point_mis_kernel(),
        KernelSource::VisOpt => shaders::visopt_kernel(),
        KernelSource::Ament => shaders::ament_kernel(),
    };
    let module = gpu.checked("kernel", || {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(scene.integrator.name()),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
    })?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let pixels = (w as u64) * (h as u64);
    let frame_buf = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("frame"),
        size: std::mem::size_of::<Frame>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let zeroed = |label: &str, size: u64| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    };
    let sum = zeroed("accum_sum", pixels * 16);
    let sq = zeroed("accum_sq", pixels * 16);
    let lookups = zeroed("accum_lookups", pixels * 4);
    let frame_layout = frame_bind_group_layout(device);
    let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout: &frame_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: sum.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: sq.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: lookups.as_entire_binding(),
            },
        ],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("transmittance"),
        bind_group_layouts: &[
            Some(&media.bind_group_layout),
            Some(&frame_layout),
            lights.as_ref().map(|l| &l.bind_group_layout),
            group3.map(|g| g.0),
        ],
        immediate_size: 0,
    });
    let mut constants = vec![("ESTIMATOR", est.id as f64)];
    if kernel.source == KernelSource::PointMis {
        constants.push(("STRATEGY", kernel.sampler as f64));
    }
    let pipeline = gpu.checked("transmittance pipeline", || {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("transmittance"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            },
            cache: None,
        })
    })?;
    let (origin, forward, right, up, tan_half) = scene.camera.basis();
    let v4 = |v: glam::Vec3| [v.x, v.y, v.z, 0.0];
    let mut frame = Frame {
        cam_origin: v4(origin),
        cam_forward: v4(forward),
        cam_right: v4(right),
        cam_up: v4(up),
        background: v4(kernel.background),
        tan_half,
        width: w,
        height: h,
        seed: opts.seed,
        first_sample: 0,
        sample_count: 0,
        media_count: scene.media.len() as u32,
        pixel_jitter: scene.pixel_jitter as u32,
        est_samples: est.samples,
        est_step: est.step,
        est_flags: est.flags,
        max_depth: kernel.max_depth,
        rr_depth: kernel.rr_depth,
        sampler: kernel.sampler,
        mis_samples: kernel.mis_samples,
        integrator_flags: kernel.flags,
        pin_mode: pin_mode_id(kernel.pins.mode),
        march_step: kernel.pins.march_step,
        pin_mask_iterations: kernel.pins.grid.mask_iterations,
        tile_y: 0,
        pad: [0; 3],
    };
    // Bands of rows, one dispatch each (visopt's NEE-list scratch holds a
    // band); the whole image otherwise.
    let band = visopt.as_ref().map_or(h, |v| v.band_rows).max(1);
    let dispatches = opts.spp.div_ceil(SAMPLES_PER_DISPATCH);
    let timed = gpu.timestamps && dispatches <= MAX_TIMED_DISPATCHES && dispatches > 0;
    let queries = timed.then(|| {
        let set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("kernel time"),
            ty: wgpu::QueryType::Timestamp,
            count: 2 * dispatches,
        });
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: 16 * dispatches as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        (set, resolve)
    });
    let mut start = Instant::now();
    let mut interrupted = false;
    let mut done = 0u32;
    let mut issued = 0u32;
    while done < opts.spp {
        if progress.cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        if opts.time_budget.is_some_and(|b| start.elapsed() >= b) {
            break;
        }
        let n = SAMPLES_PER_DISPATCH.min(opts.spp - done);
        frame.first_sample = done;
        frame.sample_count = n;
        let mut enc = device.create_command_encoder(&Default::default());
        let bands = h.div_ceil(band);
        for b in 0..bands {
            frame.tile_y = b * band;
            // A write lands before the next submission, so each band is
            // submitted with its own frame.
            gpu.queue
                .write_buffer(&frame_buf, 0, bytemuck::bytes_of(&frame));
            // The dispatch's kernel time spans its first to its last band.
            let tw = queries
                .as_ref()
                .filter(|_| b == 0 || b + 1 == bands)
                .map(|(set, _)| wgpu::ComputePassTimestampWrites {
                    query_set: set,
                    beginning_of_pass_write_index: (b == 0).then_some(2 * issued),
                    end_of_pass_write_index: (b + 1 == bands).then_some(2 * issued + 1),
                });
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("render"),
                    timestamp_writes: tw,
                });
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &media.bind_group, &[]);
                pass.set_bind_group(1, &frame_group, &[]);
                if let Some(l) = &lights {
                    pass.set_bind_group(2, &l.bind_group, &[]);
                }
                if let Some((_, group)) = group3 {
                    pass.set_bind_group(3, group, &[]);
                }
                pass.dispatch_workgroups(w.div_ceil(8), band.min(h - frame.tile_y).div_ceil(8), 1);
            }
            if b + 1 < bands {
                gpu.queue.submit([enc.finish()]);
                enc = device.create_command_encoder(&Default::default());
            }
        }
        gpu.queue.submit([enc.finish()]);
        // Wait, so progress, cancellation and the time budget see real time.
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError(format!("device poll failed: {e}")))?;
        issued += 1;
        done += n;
        after_passes(progress, n, pixels, &mut after, &mut start, || {
            read_film(gpu, w, h, &sum, &sq, &lookups)
        })?;
    }
    let seconds = start.elapsed().as_secs_f64();
    let gpu_ms = match &queries {
        Some((set, resolve)) if issued > 0 => {
            let mut enc = device.create_command_encoder(&Default::default());
            enc.resolve_query_set(set, 0..2 * issued, resolve, 0);
            gpu.queue.submit([enc.finish()]);
            let raw = gpu.read_back(resolve)?;
            let ticks: &[u64] = bytemuck::cast_slice(&raw[..16 * issued as usize]);
            let period = gpu.queue.get_timestamp_period() as f64;
            Some(
                ticks
                    .chunks(2)
                    .map(|c| c[1].saturating_sub(c[0]) as f64)
                    .sum::<f64>()
                    * period
                    * 1e-6,
            )
        }
        _ => None,
    };
    let film = read_film(gpu, w, h, &sum, &sq, &lookups)?;
    Ok(GpuRender {
        film,
        seconds,
        gpu_ms,
        interrupted,
        upload_bytes: media.bytes
            + pins.as_ref().map_or(0, |p| p.bytes)
            + visopt.as_ref().map_or(0, |v| v.bytes),
    })
}

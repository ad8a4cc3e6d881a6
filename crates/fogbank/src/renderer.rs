//! Where a film is rendered: the CPU's worker pool (the reference) or a GPU
//! (wgpu compute), behind one call, so that every front end renders a
//! scene the same way. The image is a function of scene, seed and sample
//! index only: not of the thread count, the device's batching or who asks.

use crate::error::Error;
use fogbank_render::shard::Piece;
use fogbank_render::{render_piece_observed, Film, Progress, RenderOptions, Scene};
use std::sync::Arc;

/// The device a front end asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Device {
    Cpu,
    Gpu,
}

impl Device {
    pub fn parse(s: &str) -> Result<Device, Error> {
        match s {
            "cpu" => Ok(Device::Cpu),
            "gpu" => Ok(Device::Gpu),
            other => Err(Error::invalid(format!("device `{other}` (cpu or gpu)"))),
        }
    }
}

enum Backend {
    Cpu(rayon::ThreadPool),
    Gpu(Arc<fogbank_gpu::Gpu>),
}

/// A device ready to render: a worker pool of `threads`, or an opened GPU.
pub struct Renderer {
    backend: Backend,
    threads: usize,
}

/// What a render calls after each pass: (film, seconds so far). `Send`,
/// since the CPU's passes run in its worker pool.
pub type Observer<'a> = &'a mut (dyn FnMut(&Film, f64) + Send);

/// A rendered film and how it went.
pub struct Rendered {
    pub film: Film,
    /// Seconds in the render loop (scene building and uploads excluded).
    pub seconds: f64,
    /// Stopped by `Progress::cancel` before the last pass.
    pub interrupted: bool,
    /// GPU kernel time from timestamp queries, when the device has them.
    pub gpu_ms: Option<f64>,
    /// Command buffers the GPU render submitted.
    pub gpu_submits: Option<u32>,
}

/// The worker count `threads` asks for: all cores when `None`.
pub fn threads_or_all(threads: Option<usize>) -> Result<usize, Error> {
    let n = threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    if n == 0 {
        return Err(Error::invalid("threads must be at least 1"));
    }
    Ok(n)
}

impl Renderer {
    /// The CPU with `threads` workers (all cores when `None`), or the first
    /// GPU adapter (an error naming why there is none).
    pub fn new(device: Device, threads: Option<usize>) -> Result<Renderer, Error> {
        let threads = threads_or_all(threads)?;
        match device {
            Device::Cpu => Renderer::cpu(threads),
            Device::Gpu => fogbank_gpu::Gpu::new()
                .map(|g| Renderer::gpu(Arc::new(g), threads))
                .map_err(|e| Error::runtime(format!("--device gpu: {e}"))),
        }
    }

    pub fn cpu(threads: usize) -> Result<Renderer, Error> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::runtime(e.to_string()))?;
        Ok(Renderer {
            backend: Backend::Cpu(pool),
            threads,
        })
    }

    /// An already opened GPU (the viewer keeps one for its whole session).
    pub fn gpu(gpu: Arc<fogbank_gpu::Gpu>, threads: usize) -> Renderer {
        Renderer {
            backend: Backend::Gpu(gpu),
            threads,
        }
    }

    pub fn threads(&self) -> usize {
        self.threads
    }

    pub fn device(&self) -> Device {
        match &self.backend {
            Backend::Cpu(_) => Device::Cpu,
            Backend::Gpu(_) => Device::Gpu,
        }
    }

    /// The GPU, when this renders on one.
    pub fn gpu_device(&self) -> Option<&fogbank_gpu::Gpu> {
        match &self.backend {
            Backend::Gpu(g) => Some(g),
            Backend::Cpu(_) => None,
        }
    }

    /// `cpu` or `gpu: ADAPTER (BACKEND)`, as `--stats` reports it.
    pub fn describe(&self) -> String {
        match &self.backend {
            Backend::Cpu(_) => "cpu".into(),
            Backend::Gpu(g) => format!("gpu: {}", g.describe()),
        }
    }

    /// Runs `f` inside the CPU's pool (directly on a GPU renderer).
    pub fn install<T: Send>(&self, f: impl FnOnce() -> T + Send) -> T {
        match &self.backend {
            Backend::Cpu(pool) => pool.install(f),
            Backend::Gpu(_) => f(),
        }
    }

    /// Renders `piece` of `scene` (the GPU renders whole images only),
    /// calling `after(film, seconds)` after every pass when given.
    pub fn render(
        &self,
        scene: &Scene,
        opts: &RenderOptions,
        piece: &Piece,
        progress: &Progress,
        after: Option<Observer>,
    ) -> Result<Rendered, Error> {
        match &self.backend {
            Backend::Cpu(pool) => {
                let r = pool.install(|| {
                    let after = after.map(|f| f as &mut dyn FnMut(&Film, f64));
                    render_piece_observed(scene, opts, piece, progress, after)
                });
                Ok(Rendered {
                    film: r.film,
                    seconds: r.seconds,
                    interrupted: r.interrupted,
                    gpu_ms: None,
                    gpu_submits: None,
                })
            }
            Backend::Gpu(gpu) => {
                if *piece != Piece::whole(opts.spp) {
                    return Err(Error::invalid(
                        "--device gpu renders whole images: GPU films keep running means in f32, whose parts do not add up bit for bit; shard CPU renders",
                    ));
                }
                let after = after.map(|f| f as &mut dyn FnMut(&Film, f64));
                let r = fogbank_gpu::render::render_observed(gpu, scene, opts, progress, after)
                    .map_err(|e| Error::runtime(format!("--device gpu: {e}")))?;
                Ok(Rendered {
                    film: r.film,
                    seconds: r.seconds,
                    interrupted: r.interrupted,
                    gpu_ms: r.gpu_ms,
                    gpu_submits: Some(r.submits),
                })
            }
        }
    }
}

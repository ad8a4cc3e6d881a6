//! Where an experiment renders: the CPU renderer (the reference) or the
//! wgpu backend. Experiments take it as a value, so that one function
//! serves both.

use fogbank_gpu::render::Observer;
use fogbank_gpu::Gpu;
use fogbank_render::{Progress, RenderOptions, RenderResult, Scene};

#[derive(Clone, Copy)]
pub enum Backend<'a> {
    /// fogbank's CPU renderer, in the current rayon pool.
    Cpu,
    /// The wgpu compute kernels on this device.
    Gpu(&'a Gpu),
}

impl<'a> From<Option<&'a Gpu>> for Backend<'a> {
    /// The GPU when there is one, else the CPU.
    fn from(gpu: Option<&'a Gpu>) -> Self {
        gpu.map_or(Backend::Cpu, Backend::Gpu)
    }
}

impl Backend<'_> {
    /// `cpu` or `gpu`, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu(_) => "gpu",
        }
    }

    /// Renders `scene`. The result's `seconds` is the render loop's wall
    /// clock on the CPU, and on the GPU the kernel time from timestamp
    /// queries when the device has them (else the wall clock).
    pub fn render(
        self,
        scene: &Scene,
        opts: &RenderOptions,
        progress: &Progress,
    ) -> Result<RenderResult, String> {
        self.render_observed(scene, opts, progress, None)
    }

    /// [`Backend::render`], calling `observe(film, seconds)` with the film
    /// so far after every pass (CPU) or dispatch (GPU, the film read back);
    /// time spent in `observe` and reading back is not counted.
    pub fn render_observed(
        self,
        scene: &Scene,
        opts: &RenderOptions,
        progress: &Progress,
        observe: Option<Observer<'_>>,
    ) -> Result<RenderResult, String> {
        match self {
            Backend::Cpu => Ok(match observe {
                Some(f) => fogbank_render::render_observed(scene, opts, progress, f),
                None => fogbank_render::render(scene, opts, progress),
            }),
            Backend::Gpu(gpu) => {
                let r = fogbank_gpu::render::render_observed(gpu, scene, opts, progress, observe)
                    .map_err(|e| e.0)?;
                Ok(RenderResult {
                    film: r.film,
                    seconds: r.gpu_ms.map_or(r.seconds, |ms| ms / 1000.0),
                    interrupted: r.interrupted,
                })
            }
        }
    }
}

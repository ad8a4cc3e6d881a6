//! Arguments shared by the commands that measure an estimator on a scene
//! (`stats`, `converge`).

use crate::render_cmd::DeviceArg as Device;
use clap::Args;

#[derive(Args)]
pub struct RunArgs {
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    #[arg(long)]
    pub threads: Option<usize>,
    /// Override a scene key, as in `render`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// `cpu` (the reference) or `gpu` (wgpu compute).
    #[arg(long, value_enum, default_value_t = Device::Cpu)]
    pub device: Device,
}

impl RunArgs {
    /// The rayon pool of `--threads`.
    pub fn pool(&self) -> Result<rayon::ThreadPool, Box<dyn std::error::Error>> {
        crate::common::thread_pool(self.threads)
    }

    /// The GPU with `--device gpu`, `None` with `--device cpu`.
    pub fn gpu(&self) -> Result<Option<fogbank_gpu::Gpu>, String> {
        match self.device {
            Device::Cpu => Ok(None),
            Device::Gpu => fogbank_gpu::Gpu::new()
                .map(Some)
                .map_err(|e| format!("--device gpu: {e}")),
        }
    }
}

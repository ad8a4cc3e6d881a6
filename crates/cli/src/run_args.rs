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

//! `fogbank view`: the interactive viewer (see the `fogbank_viewer` crate).

use crate::common::CliResult;
use clap::Args;
use fogbank_viewer::{DeviceChoice, ViewOptions};
use std::path::PathBuf;
use std::time::Duration;

#[derive(Args)]
pub struct ViewArgs {
    /// Scene file: fogbank TOML (`.toml`), Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`). Without it, the built-in default scene.
    pub scene: Option<PathBuf>,
    /// Override a scene key: `--set integrator.estimator=track_length`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Where to render: `auto` (the GPU when an adapter exists, else the
    /// CPU), `cpu` or `gpu`.
    #[arg(long, value_enum, default_value_t = Device::Auto)]
    pub device: Device,
    /// CPU worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Stop accumulating at this many samples per pixel.
    #[arg(long, default_value_t = 1 << 16)]
    pub spp: u32,
    /// Play the steps of this TOML file (orbit, set, wait, screenshot,
    /// save, quit) in the window; see the viewer's `script` module.
    #[arg(long)]
    pub script: Option<PathBuf>,
    /// A script still running after this many seconds fails.
    #[arg(long, default_value_t = 600.0)]
    pub script_timeout: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    Auto,
    Cpu,
    Gpu,
}

pub fn run(a: ViewArgs) -> CliResult {
    if a.spp == 0 {
        return Err("--spp must be at least 1".into());
    }
    fogbank_viewer::run(ViewOptions {
        scene: a.scene,
        overrides: a.set,
        device: match a.device {
            Device::Auto => DeviceChoice::Auto,
            Device::Cpu => DeviceChoice::Cpu,
            Device::Gpu => DeviceChoice::Gpu,
        },
        threads: a.threads,
        max_spp: a.spp,
        script: a.script,
        script_timeout: Duration::from_secs_f64(a.script_timeout.max(1.0)),
    })?;
    Ok(())
}

//! `fogbank export SCENE -o OUT.{vdb,nvdb}`: writes a scene medium's grid
//! as a volume file (the work is `fogbank::export`).

use crate::common::CliResult;
use crate::volume_write_args::VolumeWriteArgs;
use clap::Args;
use fogbank::export::{export, ExportGrid, ExportOptions};
use std::path::PathBuf;

#[derive(Args)]
pub struct ExportArgs {
    /// Scene file: fogbank TOML (`.toml`), Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`).
    pub scene: PathBuf,
    /// The file to write: `.vdb` (OpenVDB) or `.nvdb` (NanoVDB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Index of the medium in the scene's `[[media]]`.
    #[arg(long, default_value_t = 0)]
    pub medium: usize,
    /// `density`, or `temperature` (of the medium's emission).
    #[arg(long, default_value = "density")]
    pub grid: String,
    #[command(flatten)]
    pub write: VolumeWriteArgs,
}

pub fn run(a: ExportArgs) -> CliResult {
    let grid = match a.grid.as_str() {
        "density" => ExportGrid::Density,
        "temperature" => ExportGrid::Temperature,
        g => return Err(format!("--grid {g}: expected density or temperature").into()),
    };
    let (codec, value) = a.write.parse()?;
    let options = ExportOptions {
        medium: a.medium,
        grid,
        half: a.write.half,
        codec,
        value,
    };
    let done = export(&a.scene, &a.output, &options)?;
    println!(
        "{}: grid `{}`, {} active voxels in {} leaves, {} bytes",
        a.output.display(),
        done.grid,
        done.active_voxels,
        done.leaves,
        done.bytes
    );
    Ok(())
}

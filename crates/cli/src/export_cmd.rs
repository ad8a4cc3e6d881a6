//! `fogbank export SCENE -o OUT.{vdb,nvdb}`: writes a scene medium's grid
//! as a volume file (the work is `fogbank_render::export`).

use crate::common::CliResult;
use clap::Args;
use fogbank_render::export::{export, ExportGrid, ExportOptions};
use fogbank_volume::writers::{Codec, NanoValue};
use std::path::PathBuf;

#[derive(Args)]
pub struct ExportArgs {
    /// The scene file (fogbank TOML, Mitsuba XML or pbrt-v4).
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
    /// `.vdb` only: store values as half floats.
    #[arg(long)]
    pub half: bool,
    /// none, zip or blosc.
    #[arg(long, default_value = "none")]
    pub codec: String,
    /// `.nvdb` only: quantise leaves to fp8 or fp16 (default: float).
    #[arg(long)]
    pub quantise: Option<String>,
}

pub fn run(a: ExportArgs) -> CliResult {
    let grid = match a.grid.as_str() {
        "density" => ExportGrid::Density,
        "temperature" => ExportGrid::Temperature,
        g => return Err(format!("--grid {g}: expected density or temperature").into()),
    };
    let codec = Codec::parse(&a.codec)
        .ok_or_else(|| format!("--codec {}: expected none, zip or blosc", a.codec))?;
    let value = match a.quantise.as_deref() {
        None => NanoValue::Float,
        Some(q) => NanoValue::parse(q)
            .filter(|v| *v != NanoValue::Float)
            .ok_or_else(|| format!("--quantise {q}: expected fp8 or fp16"))?,
    };
    let options = ExportOptions {
        medium: a.medium,
        grid,
        half: a.half,
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

//! `fogbank convert IN -o OUT`: scenes between pbrt-v4, Mitsuba XML and
//! TOML, volumes to .vdb/.nvdb (the work is `fogbank_render::convert`).

use crate::common::CliResult;
use clap::Args;
use fogbank_render::convert::{convert, ConvertOptions};
use fogbank_volume::writers::{Codec, NanoValue};
use std::path::PathBuf;

#[derive(Args)]
pub struct ConvertArgs {
    /// The file to convert: a scene (.toml, .xml, .pbrt) or a volume
    /// (.vdb, .nvdb, .vol, .nii, .nii.gz, .hdr, .nrrd, .nhdr).
    pub input: PathBuf,
    /// The file to write: a scene as .toml or .xml (Mitsuba 3), a volume
    /// (or a scene's medium) as .vdb or .nvdb.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The grid to convert: a grid name of a .vdb/.nvdb file (default
    /// `density`, else the first float grid); for a scene's medium,
    /// `density` or `temperature`.
    #[arg(long)]
    pub grid: Option<String>,
    /// For a scene written as a volume: index of the medium in `[[media]]`.
    #[arg(long, default_value_t = 0)]
    pub medium: usize,
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

pub fn run(a: ConvertArgs) -> CliResult {
    let codec = Codec::parse(&a.codec)
        .ok_or_else(|| format!("--codec {}: expected none, zip or blosc", a.codec))?;
    let value = match a.quantise.as_deref() {
        None => NanoValue::Float,
        Some(q) => NanoValue::parse(q)
            .filter(|v| *v != NanoValue::Float)
            .ok_or_else(|| format!("--quantise {q}: expected fp8 or fp16"))?,
    };
    let options = ConvertOptions {
        grid: a.grid,
        medium: a.medium,
        half: a.half,
        codec,
        value,
    };
    let done = convert(&a.input, &a.output, &options)?;
    for n in &done.notes {
        eprintln!("note: {n}");
    }
    println!("{}", done.summary);
    Ok(())
}

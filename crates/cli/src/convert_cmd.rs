//! `fogbank convert IN -o OUT`: scenes between pbrt-v4, Mitsuba XML and
//! TOML, volumes to .vdb/.nvdb (the work is `fogbank::convert`).

use crate::common::CliResult;
use crate::volume_write_args::VolumeWriteArgs;
use clap::Args;
use fogbank::convert::{convert, ConvertOptions};
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
    #[command(flatten)]
    pub write: VolumeWriteArgs,
}

pub fn run(a: ConvertArgs) -> CliResult {
    let (codec, value) = a.write.parse()?;
    let options = ConvertOptions {
        grid: a.grid,
        medium: a.medium,
        half: a.write.half,
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

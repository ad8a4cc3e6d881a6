//! `fogbank info FILE`: what a volume file holds and what fogbank would make
//! of it (`fogbank::info`).

use crate::common::CliResult;
use clap::Args;
use fogbank::info::{describe_volume, VolumeQuery};
use std::path::PathBuf;

#[derive(Args)]
pub struct InfoArgs {
    /// A volume file: .vdb (OpenVDB), .nvdb (NanoVDB), .vol (Mitsuba), .nii, .nii.gz or .hdr
    /// (NIfTI), .nrrd or .nhdr (NRRD), or .raw (with --dims and --type).
    pub file: PathBuf,
    /// Raw files: dimensions X Y Z (else parsed from `name_XxYxZ_type.raw`).
    #[arg(long, num_args = 3)]
    pub dims: Option<Vec<u32>>,
    /// Raw files: u8, u16, i16, f32, f64.
    #[arg(long = "type")]
    pub ty: Option<String>,
}

pub fn run(a: InfoArgs) -> CliResult {
    let query = VolumeQuery {
        file: a.file,
        dims: a.dims.map(|d| [d[0], d[1], d[2]]),
        ty: a.ty,
    };
    print!("{}", describe_volume(&query)?);
    Ok(())
}

//! `fogbank info FILE` as a library call: what a volume file holds — its
//! format, grids, value range, placement (each format's description,
//! `fogbank_volume::formats`) — and what fogbank would make of it
//! (its brick grid's memory, the default pin grid), as the text the command
//! prints.

use crate::error::Error;
use fogbank_render::integrators::shared::pin_params::PinGridParams;
use fogbank_volume::formats::{self, Described};
use fogbank_volume::{BrickGrid, DensityData, Precision};
use std::fmt::Write;

/// The file to describe, with what a raw file's name may not say.
pub use fogbank_volume::formats::VolumeQuery;

/// What `fogbank info` prints about `query.file`; an error naming the file
/// when it cannot be read.
pub fn describe_volume(query: &VolumeQuery) -> Result<String, Error> {
    let mut out = String::new();
    describe_into(&mut out, query).map_err(|e| Error::from_message(e.to_string()))?;
    Ok(out)
}

/// `writeln!` into the description; writing into a `String` cannot fail.
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {{
        let _ = writeln!($out, $($arg)*);
    }};
}

fn print_memory(out: &mut String, grid: BrickGrid<f32>) {
    let dims = grid.dims();
    let voxels = dims.iter().map(|&d| d as f64).product::<f64>();
    let d16 = DensityData::from_f32(grid, Precision::F16);
    let bytes = d16.memory_bytes();
    let (dense, total) = match &d16 {
        DensityData::F16(g) => (g.dense_bricks(), g.brick_count()),
        _ => (0, 0),
    };
    say!(
            out,
        "  fogbank grid: {}×{}×{} voxels, {dense}/{total} dense 8³ bricks, {:.1} MiB as f16 ({:.3} bytes/voxel)",
        dims[0],
        dims[1],
        dims[2],
        bytes as f64 / (1 << 20) as f64,
        bytes as f64 / voxels
    );
    // Hansen 2025's default pin grid for this volume (0.1× the f16 texture).
    let g = PinGridParams::default();
    let p = g.positions_for(voxels as u64);
    let pins = (p as u64).pow(3) * (g.phi * g.theta) as u64;
    say!(
            out,
        "  pin grid (pins = \"ms\", default): {p}³ positions × {} directions = {pins} pins, {:.2} MiB",
        g.phi * g.theta,
        (pins * 8) as f64 / (1 << 20) as f64
    );
}

fn describe_into(out: &mut String, a: &VolumeQuery) -> Described {
    match formats::of_path(&a.file) {
        Some(format) => (format.describe)(out, a, &print_memory),
        None => Err(format!(
            "{}: unknown volume format (expected {})",
            a.file.display(),
            formats::expected_extensions()
        )
        .into()),
    }
}

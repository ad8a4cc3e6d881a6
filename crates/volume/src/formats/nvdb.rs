//! NanoVDB (`nvdb = "f.nvdb"`): float, double, Fp4/Fp8/Fp16/FpN grids,
//! uncompressed, ZIP or BLOSC; `grid` and `level_set` as for OpenVDB.
//! fogbank's own reader (`crate::loaders::nanovdb`), its leaves
//! streamed into bricks, and writer.

use crate::VolumeError;
use super::format::{Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery, WriteOptions};
use super::sparse::{grid_file_info, level_set_mode, value_map, GridFormat};
use crate::loaders::{nanovdb, vdb};
use crate::writers::{self, NanoOptions};
use crate::{DensityData, Precision};
use std::path::Path;

pub const FORMAT: VolumeFormat = VolumeFormat {
    key: "nvdb",
    name: "NanoVDB",
    extensions: &[".nvdb"],
    by_extension: true,
    read,
    describe,
    sparse: Some(nanovdb::read_grid),
    write: Some(write),
};

const NANOVDB: GridFormat = GridFormat {
    name: "NanoVDB",
    list: nanovdb::list_grids,
    read: nanovdb::read_grid,
    version: |v| format!("NanoVDB {}", nanovdb::version_string(v)),
};

/// A NanoVDB file's float grid, its leaves streamed from the file into
/// bricks of the medium's precision (the same bricks OpenVDB's reader makes
/// of the grid, without ever holding the file's voxels).
fn read(s: &FileSource, precision: Precision) -> crate::Result<FieldData> {
    let mut mode = Ok(false);
    let choose = |g: &vdb::VdbGrid| {
        mode = level_set_mode(s, g);
        value_map(g, *mode.as_ref().unwrap_or(&false))
    };
    let (data, xf, g) = match precision {
        Precision::F16 => {
            let (b, xf, g) =
                nanovdb::read_grid_bricks(s.path, s.grid, choose).map_err(|e| s.error(e))?;
            (DensityData::F16(b), xf, g)
        }
        Precision::F32 => {
            let (b, xf, g) =
                nanovdb::read_grid_bricks(s.path, s.grid, choose).map_err(|e| s.error(e))?;
            (DensityData::F32(b), xf, g)
        }
    };
    mode?;
    let what = format!("{} ({})", s.path.display(), g.name);
    Ok(FieldData::new(data, xf, what))
}

fn describe(out: &mut String, a: &VolumeQuery, footprint: Footprint) -> Described {
    grid_file_info(out, a, footprint, &NANOVDB)
}

/// NanoVDB stores float or quantised values.
fn write(grid: &vdb::VdbGrid, out: &Path, o: &WriteOptions) -> crate::Result<Vec<u8>> {
    if o.half {
        return Err(VolumeError::Invalid(
            "half floats are an OpenVDB (.vdb) option; NanoVDB quantises with fp8 or fp16".into(),
        ));
    }
    let options = NanoOptions {
        value: o.value,
        codec: o.codec,
    };
    writers::nanovdb::to_bytes(std::slice::from_ref(grid), options)
        .map_err(|e| VolumeError::Invalid(format!("{}: {e}", out.display())))
}

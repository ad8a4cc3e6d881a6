//! OpenVDB (`vdb = "f.vdb"`): sparse float grids; `grid` (default
//! `density`, else the first float grid), `level_set` = `"fog"` (default)
//! or `"raw"`. fogbank's own reader (`crate::loaders::vdb`) and
//! writer; the file's leaves become the medium's bricks.

use crate::VolumeError;
use super::format::{Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery, WriteOptions};
use super::sparse::{grid_file_info, level_set_mode, value_map, GridFormat};
use crate::loaders::{vdb, vdb_grid};
use crate::writers::{self, Codec, NanoValue, VdbOptions};
use crate::{DensityData, Precision};
use std::path::Path;

pub const FORMAT: VolumeFormat = VolumeFormat {
    key: "vdb",
    name: "OpenVDB",
    extensions: &[".vdb"],
    by_extension: true,
    read,
    describe,
    sparse: Some(vdb::read_grid),
    write: Some(write),
};

const OPENVDB: GridFormat = GridFormat {
    name: "OpenVDB",
    list: vdb::list_grids,
    read: vdb::read_grid,
    version: |v| format!("file version {v}"),
};

/// An OpenVDB grid, its leaves the bricks (level sets as fog unless `raw`).
fn read(s: &FileSource, precision: Precision) -> crate::Result<FieldData> {
    let g = vdb::read_grid(s.path, s.grid).map_err(|e| s.error(e))?;
    let mode = level_set_mode(s, &g)?;
    let name = g.name.clone();
    let map = value_map(&g, mode);
    // The file's leaves become the builder's bricks, and each brick is
    // mapped and stored in the medium's precision as it is finished:
    // the voxels exist in f32 once.
    let (builder, xf) = vdb_grid::to_builder(g).map_err(|e| s.error(e))?;
    let data = match precision {
        Precision::F16 => DensityData::F16(builder.finish_converted(map)),
        Precision::F32 => DensityData::F32(builder.finish_converted(map)),
    };
    let what = format!("{} ({name})", s.path.display());
    Ok(FieldData::new(data, xf, what))
}

fn describe(out: &mut String, a: &VolumeQuery, footprint: Footprint) -> Described {
    grid_file_info(out, a, footprint, &OPENVDB)
}

/// OpenVDB stores float or half values.
fn write(grid: &vdb::VdbGrid, out: &Path, o: &WriteOptions) -> crate::Result<Vec<u8>> {
    if o.value != NanoValue::Float {
        return Err(VolumeError::Invalid(
            "quantisation (fp8, fp16) is a NanoVDB (.nvdb) option; OpenVDB stores float or half"
                .into(),
        ));
    }
    let options = VdbOptions {
        half: o.half,
        codec: o.codec,
        active_mask: o.codec != Codec::None,
    };
    writers::vdb::to_bytes(std::slice::from_ref(grid), options)
        .map_err(|e| VolumeError::Invalid(format!("{}: {e}", out.display())))
}

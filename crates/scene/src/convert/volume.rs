//! Volume files converted to OpenVDB (`.vdb`) or NanoVDB (`.nvdb`).
//!
//! A `.vdb` or `.nvdb` source is copied grid to grid: the sparse tree the
//! reader returns (leaves, masks, tiles, background, index→world map) is
//! what the writer writes, so every active voxel and its value is kept
//! (quantised `.nvdb` sources are read as the floats they decode to).
//! Dense sources (`.vol`, NIfTI, NRRD) are read as a one-medium scene
//! reads them — placed in world space as fogbank places them, NIfTI and
//! NRRD values rescaled onto [0, 1] — and written by
//! [`export_desc`], as `fogbank export` writes
//! a medium.

use super::output::{write_file, ConvertOptions, Converted};
use crate::export::{export_desc, ExportGrid, ExportOptions, Exported};
use fogbank_render::error::SceneError;
use fogbank_render::scene::parse_scene;
use fogbank_volume::formats;
use fogbank_volume::loaders::vdb::VdbGrid;
use std::path::Path;

/// The sparse grid `name` (default: `density`, else the first float grid)
/// of the `.vdb` or `.nvdb` file `input`.
pub fn read_sparse(input: &Path, key: &str, name: Option<&str>) -> Result<VdbGrid, SceneError> {
    let read = formats::by_key(key).and_then(|f| f.sparse).ok_or_else(|| {
        SceneError(format!(
            "{}: `{key}` is not a sparse format",
            input.display()
        ))
    })?;
    read(input, name).map_err(|e| SceneError(format!("{}: {e}", input.display())))
}

/// `grid` encoded for `out` with `options` (as `fogbank export` encodes).
pub fn encode(grid: &VdbGrid, out: &Path, options: &ConvertOptions) -> Result<Vec<u8>, SceneError> {
    crate::export::encode(grid, out, options.half, options.codec, options.value)
}

/// Converts the volume file `input`, read with field key `key` (`vdb`,
/// `nvdb`, `vol`, `nifti`, `nrrd`), to the `.vdb`/`.nvdb` file `output`.
pub fn convert(
    input: &Path,
    key: &str,
    output: &Path,
    options: &ConvertOptions,
) -> Result<Converted, SceneError> {
    if formats::by_key(key).is_some_and(|f| f.sparse.is_some()) {
        let grid = read_sparse(input, key, options.grid.as_deref())?;
        let bytes = encode(&grid, output, options)?;
        write_file(output, &bytes)?;
        return Ok(summary(
            output,
            &Exported {
                grid: grid.name.clone(),
                leaves: grid.leaves.len(),
                active_voxels: grid.active_voxel_count(),
                bytes: bytes.len(),
            },
        ));
    }
    if let Some(g) = &options.grid {
        return Err(SceneError(format!(
            "--grid {g}: {} holds one volume (a grid is chosen in .vdb and .nvdb files only)",
            input.display()
        )));
    }
    let abs =
        std::path::absolute(input).map_err(|e| SceneError(format!("{}: {e}", input.display())))?;
    let text = format!(
        "[[media]]\ndensity = {{ {key} = {} }}\nprecision = \"f32\"\n",
        toml::Value::String(abs.display().to_string())
    );
    let desc = parse_scene(&text, &input.display().to_string(), &[])?;
    let export = ExportOptions {
        medium: 0,
        grid: ExportGrid::Density,
        half: options.half,
        codec: options.codec,
        value: options.value,
    };
    let done = export_desc(&desc, Path::new("."), output, &export)?;
    Ok(summary(output, &done))
}

/// A grid of the scene `input`'s medium `options.medium` (`--grid`:
/// `density`, the default, or `temperature`), as `fogbank export` writes it.
pub fn from_scene(
    input: &Path,
    output: &Path,
    options: &ConvertOptions,
) -> Result<Converted, SceneError> {
    let grid = match options.grid.as_deref() {
        None | Some("density") => ExportGrid::Density,
        Some("temperature") => ExportGrid::Temperature,
        Some(g) => {
            return Err(SceneError(format!(
                "--grid {g}: a scene's medium has the grids density and temperature"
            )))
        }
    };
    let export = ExportOptions {
        medium: options.medium,
        grid,
        half: options.half,
        codec: options.codec,
        value: options.value,
    };
    let done = crate::export::export(input, output, &export)?;
    Ok(summary(output, &done))
}

fn summary(output: &Path, done: &Exported) -> Converted {
    Converted {
        summary: format!(
            "{}: grid `{}`, {} active voxels in {} leaves, {} bytes",
            output.display(),
            done.grid,
            done.active_voxels,
            done.leaves,
            done.bytes
        ),
        notes: Vec::new(),
    }
}

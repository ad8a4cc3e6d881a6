//! Writing a scene medium's grid as a volume file: its density (or the
//! temperature of its emission) as built for rendering, procedural media
//! voxelised, with the medium's `to_world` folded into the file's
//! index→world map, as OpenVDB `.vdb` or NanoVDB `.nvdb` chosen by the
//! output's extension (see `fogbank_volume::writers`).
//!
//! Reading the file back (`vdb = "out.vdb"` or `nvdb = "out.nvdb"` with no
//! `to_world`) gives the same voxels at the same world positions, so a
//! float export renders as the original medium.

use std::path::Path;

use fogbank_volume::formats::{self, WriteOptions};
use fogbank_volume::loaders::vdb::VdbGrid;
use fogbank_volume::writers;
/// How a `.vdb` compresses its leaves and what a `.nvdb` stores per voxel.
pub use fogbank_volume::writers::{Codec, NanoValue};
use fogbank_volume::{DensityData, Precision};

use crate::load::read_scene_source;
use fogbank_render::error::SceneError;
use fogbank_render::scene::{parse_scene, SceneDesc};
use fogbank_render::world::field::{field_data, FieldDesc};
use fogbank_render::world::medium::transform;

/// Which of the medium's grids to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ExportGrid {
    #[default]
    Density,
    /// The temperature grid of the medium's emission.
    Temperature,
}

impl ExportGrid {
    /// The grid's name in the file.
    pub fn name(self) -> &'static str {
        match self {
            ExportGrid::Density => "density",
            ExportGrid::Temperature => "temperature",
        }
    }
}

/// What to write and how.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ExportOptions {
    /// Index into the scene's `[[media]]`.
    pub medium: usize,
    pub grid: ExportGrid,
    /// `.vdb` only: store values as half floats.
    pub half: bool,
    pub codec: Codec,
    /// `.nvdb` only: the value type (quantised or float).
    pub value: NanoValue,
}

/// What was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    pub grid: String,
    pub leaves: usize,
    pub active_voxels: u64,
    pub bytes: usize,
}

/// Exports a grid of the scene file `scene` (fogbank TOML or Mitsuba XML)
/// to `out`.
pub fn export(scene: &Path, out: &Path, options: &ExportOptions) -> Result<Exported, SceneError> {
    let source = read_scene_source(scene, &[])?;
    let desc = parse_scene(&source.text, &source.origin, &[])?;
    export_desc(&desc, &source.base, out, options)
}

/// Exports a grid of the parsed scene `desc`, whose files resolve against
/// `base`, to `out`.
pub fn export_desc(
    desc: &SceneDesc,
    base: &Path,
    out: &Path,
    options: &ExportOptions,
) -> Result<Exported, SceneError> {
    let grid = medium_grid(desc, base, options)?;
    let bytes = encode(&grid, out, options.half, options.codec, options.value)?;
    std::fs::write(out, &bytes).map_err(|e| SceneError(format!("{}: {e}", out.display())))?;
    Ok(Exported {
        grid: grid.name.clone(),
        leaves: grid.leaves.len(),
        active_voxels: grid.active_voxel_count(),
        bytes: bytes.len(),
    })
}

/// `grid` as the bytes of the volume file `out`: OpenVDB for `.vdb` (float,
/// or `half`), NanoVDB for `.nvdb` (float or quantised to `value`), with
/// `codec`; an option the format lacks is an error.
pub fn encode(
    grid: &VdbGrid,
    out: &Path,
    half: bool,
    codec: Codec,
    value: NanoValue,
) -> Result<Vec<u8>, SceneError> {
    let write = formats::by_extension(out)
        .and_then(|f| f.write)
        .ok_or_else(|| {
            SceneError(format!(
                "{}: the output must be a {} file",
                out.display(),
                formats::or_list(&formats::extensions(|f| f.write.is_some()))
            ))
        })?;
    write(grid, out, &WriteOptions { half, codec, value }).map_err(|e| SceneError(e.to_string()))
}

/// The chosen grid of medium `options.medium`, in world space.
pub fn medium_grid(
    desc: &SceneDesc,
    base: &Path,
    options: &ExportOptions,
) -> Result<VdbGrid, SceneError> {
    let i = options.medium;
    let m = desc.media.get(i).ok_or_else(|| {
        SceneError(format!(
            "medium {i}: the scene has {} media",
            desc.media.len()
        ))
    })?;
    let key = format!("media.{i}");
    let (field, fkey): (&FieldDesc, String) = match options.grid {
        ExportGrid::Density => (&m.density, format!("{key}.density")),
        ExportGrid::Temperature => match m.emission.as_ref().and_then(|e| e.temperature.as_ref()) {
            Some(t) => (t, format!("{key}.emission.temperature")),
            None => {
                return Err(SceneError(format!(
                    "{key}: the medium has no emission temperature grid"
                )))
            }
        },
    };
    m.to_world.check(&format!("{key}.to_world"))?;
    // Full precision: the file keeps the values the scene names; a medium
    // stored in f16 rounds them again when the file is loaded.
    let data = field_data(field, &fkey, base, Precision::F32)?;
    let xf = transform(&m.to_world) * data.to_world;
    let name = options.grid.name();
    Ok(match &data.data {
        DensityData::F32(g) => writers::from_brick_grid(g, xf, name, 0.0),
        DensityData::F16(g) => writers::from_brick_grid(g, xf, name, 0.0),
        DensityData::Analytic(_) => {
            return Err(SceneError(format!(
                "{fkey}: an analytic field has no voxels to export"
            )))
        }
    })
}

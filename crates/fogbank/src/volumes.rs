//! Voxel grids a front end hands to a scene or reads from a file: the
//! array interface a scene field reads (`{ array = NAME }`), its placement
//! in the world, and a volume file read as a scene would read it.

use crate::error::Error;
use fogbank_render::desc::FieldDesc;
use fogbank_render::world::field::field_data;
use fogbank_volume::formats;
use fogbank_volume::{DensityData, Precision};
use std::path::Path;
use std::sync::Arc;

pub use fogbank_volume::grid::check_dims;
pub use fogbank_volume::medium::{box_transform, unit_box_transform};
pub use fogbank_volume::{DenseArray, VoxelArray};

/// Makes `array` what a scene's `{ array = NAME }` names in this process,
/// and returns the name.
pub fn register_array(array: &Arc<dyn VoxelArray>) -> String {
    fogbank_render::world::arrays::register(array)
}

/// A volume file read as a scene reads it.
pub struct ReadVolume {
    /// The voxels, in fogbank's units, placed in the world.
    pub array: DenseArray,
    /// For scientific files (NIfTI, NRRD): the file's value range the
    /// grid's [0, 1] stands for.
    pub units: Option<(f32, f32)>,
}

/// Reads `path` as fogbank reads a volume for a scene: `.vdb` and `.nvdb`
/// (grid `grid`), `.vol` (channel `channel`), `.nii`/`.nii.gz`/`.hdr`,
/// `.nrrd`/`.nhdr`, `.raw` (dimensions from a `name_XxYxZ_type.raw` file
/// name); values as fogbank renders them (negative densities clamped to 0,
/// a level set as fog, scientific data normalised onto [0, 1]). Refuses
/// grids of more than `max_voxels` voxels before copying them.
pub fn read_volume(
    path: &Path,
    grid: Option<String>,
    channel: Option<u32>,
    max_voxels: u64,
) -> Result<ReadVolume, Error> {
    let name = path.to_string_lossy().to_string();
    let Some(format) = formats::of_path(path) else {
        return Err(Error::invalid(format!(
            "{name}: unknown volume format (expected {})",
            formats::expected_extensions()
        )));
    };
    if grid.is_some() && format.sparse.is_none() {
        return Err(Error::invalid(format!(
            "{name}: grid= names a grid of a {} file",
            formats::or_list(&formats::extensions(|f| f.sparse.is_some()))
        )));
    }
    let mut d = FieldDesc {
        grid,
        channel,
        ..Default::default()
    };
    d.files.set(format, name.clone());
    let f = field_data(&d, &name, Path::new(""), Precision::F32)?;
    let DensityData::F32(g) = &f.data else {
        return Err(Error::invalid(format!("{name}: not a voxel grid")));
    };
    let [x, y, z] = g.dims().map(u64::from);
    if x * y * z > max_voxels {
        return Err(Error::invalid(format!(
            "{name}: {x}×{y}×{z} voxels are more than max_voxels = {max_voxels}"
        )));
    }
    Ok(ReadVolume {
        array: DenseArray::from_grid(g, f.to_world, f.source.clone()),
        units: f.units,
    })
}

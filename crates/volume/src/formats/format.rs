//! What a volume format provides, in its own file under `formats/`: its
//! scene key and extensions, its reader (a field for a scene), its
//! description (`fogbank info`), and, for sparse formats, the grid as it is
//! stored and its writer. `formats/mod.rs` registers each in one line of
//! its `volume_formats!` list.

use crate::loaders::vdb::VdbGrid;
use crate::writers::{Codec, NanoValue};
use crate::VolumeError;
use crate::{BrickGrid, DensityData, Precision};
use fogbank_math::DAffine3;
use std::path::{Path, PathBuf};

/// One volume format.
pub struct VolumeFormat {
    /// Its key in a field's table (`density = { vdb = "f.vdb" }`).
    pub key: &'static str,
    /// What it is, for messages and listings.
    pub name: &'static str,
    /// Its file extensions, lower case with the dot.
    pub extensions: &'static [&'static str],
    /// Its files say their size, so the extension alone tells the format
    /// (`convert`, scenes by extension); a raw file's size is given.
    pub by_extension: bool,
    /// The field of a scene's source `file`.
    pub read: fn(&FileSource, Precision) -> crate::Result<FieldData>,
    /// What `fogbank info` prints about a file, each grid's footprint by
    /// the caller's `Footprint`.
    pub describe: fn(&mut String, &VolumeQuery, Footprint) -> Described,
    /// Sparse formats: the grid as stored (every active voxel, tiles and
    /// background), by name (default `density`, else the first float grid).
    pub sparse: Option<ReadSparse>,
    /// The bytes of the file `out` of this format holding `grid`.
    pub write: Option<Write>,
}

/// A sparse format's reader of one grid as stored.
pub type ReadSparse = fn(&Path, Option<&str>) -> crate::Result<VdbGrid>;

/// A format's writer: the bytes of file `out` holding a grid.
pub type Write = fn(&VdbGrid, &Path, &WriteOptions) -> crate::Result<Vec<u8>>;

/// A field's file with the keys its reader may take.
pub struct FileSource<'a> {
    /// The scene key of the field, for messages (`media.0.density`).
    pub key: &'a str,
    pub path: &'a Path,
    /// Sparse files: the grid's name.
    pub grid: Option<&'a str>,
    /// Sparse files: a level set as `fog` (default) or `raw` values.
    pub level_set: Option<&'a str>,
    /// Dense files: the channel or 3D volume of a 4D file.
    pub channel: Option<u32>,
    /// Raw files: the dimensions and the sample type.
    pub dims: Option<[u32; 3]>,
    pub ty: Option<&'a str>,
}

impl FileSource<'_> {
    /// A volume reader's error as a scene error naming the key.
    pub fn error(&self, e: impl std::fmt::Display) -> VolumeError {
        VolumeError::Invalid(format!("{}: {e}", self.key))
    }
}

/// A loaded field: its data, index→world transform and a description of
/// its source.
pub struct FieldData {
    pub data: DensityData,
    pub to_world: DAffine3,
    pub source: String,
    /// The file's value range (lo, hi) that the stored [0, 1] stands for
    /// (scientific files); `None` when the stored values are the file's.
    pub units: Option<(f32, f32)>,
}

impl FieldData {
    pub fn new(data: DensityData, to_world: DAffine3, source: String) -> Self {
        FieldData {
            data,
            to_world,
            source,
            units: None,
        }
    }
}

/// The file `fogbank info` describes, with what a raw file's name may not
/// say.
#[derive(Clone, Debug, Default)]
pub struct VolumeQuery {
    pub file: PathBuf,
    /// Raw files: dimensions X Y Z (else parsed from `name_XxYxZ_type.raw`).
    pub dims: Option<[u32; 3]>,
    /// Raw files: u8, u16, i16, f32, f64.
    pub ty: Option<String>,
}

/// What the caller prints about a grid as fogbank would store it (its
/// memory as bricks, the default pin grid).
pub type Footprint<'a> = &'a dyn Fn(&mut String, BrickGrid<f32>);

/// A description written, or why the file could not be read.
pub type Described = Result<(), Box<dyn std::error::Error>>;

/// How a grid is written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WriteOptions {
    /// OpenVDB: values as half floats.
    pub half: bool,
    pub codec: Codec,
    /// NanoVDB: the value type (float or quantised).
    pub value: NanoValue,
}

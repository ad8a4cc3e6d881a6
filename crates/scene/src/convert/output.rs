//! What a conversion takes and gives, and the writing of its file.

use fogbank_render::error::SceneError;
use fogbank_volume::writers::{Codec, NanoValue};
use std::path::Path;

/// How to convert (the volume options are those of `fogbank export`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ConvertOptions {
    /// The grid of a multi-grid volume file (default: `density`, else the
    /// first float grid); for a scene written as a volume, `density` or
    /// `temperature`.
    pub grid: Option<String>,
    /// For a scene written as a volume: the index of its medium.
    pub medium: usize,
    /// `.vdb` only: store values as half floats.
    pub half: bool,
    pub codec: Codec,
    /// `.nvdb` only: the value type (quantised or float).
    pub value: NanoValue,
}

/// What a conversion wrote: one line saying so, and the notes (anything
/// the output format could not hold, and what was done instead).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Converted {
    pub summary: String,
    pub notes: Vec<String>,
}

/// Writes `bytes` to `out`, naming it in the error.
pub fn write_file(out: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    std::fs::write(out, bytes).map_err(|e| SceneError(format!("{}: {e}", out.display())))
}

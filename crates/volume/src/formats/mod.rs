//! The volume formats fogbank reads, one file each (its scene key, its
//! extensions, its reader, its `fogbank info` description and, for sparse
//! formats, the grid as stored and its writer: a [`VolumeFormat`]),
//! registered in one line of the `volume_formats!` list below. The list is
//! what a field's table takes (`density = { nrrd = "f.nhdr" }`), what
//! `fogbank info`, `convert`, `export` and Python's `read_volume` tell by
//! extension, and what their messages and help texts name.
//!
//! Beside the formats: [`format`] (what a format provides), [`describe`]
//! (what every description prints), `sparse` (what OpenVDB and NanoVDB
//! share), `scientific` (what NIfTI and NRRD share).

pub(crate) mod describe;
pub mod format;
mod scientific;
mod sparse;

pub use format::{
    Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery, WriteOptions,
};
use std::path::Path;
use std::sync::LazyLock;

/// The formats, one line each (the module holding its `FORMAT`), in the
/// order listings name them.
macro_rules! volume_formats {
    ($($(#[$meta:meta])* $module:ident,)*) => {
        $($(#[$meta])* pub mod $module;)*

        // Entries may carry `#[cfg]`s, which `vec![]`'s elements cannot.
        #[allow(clippy::vec_init_then_push)]
        static FORMATS: LazyLock<Vec<&'static VolumeFormat>> = LazyLock::new(|| {
            let mut v: Vec<&'static VolumeFormat> = Vec::new();
            $($(#[$meta])* v.push(&$module::FORMAT);)*
            v
        });
    };
}

volume_formats! {
    vdb,
    nvdb,
    vol,
    nifti,
    nrrd,
    raw,
    #[cfg(test)]
    test_text,
}

/// Every volume format, in listing order.
pub fn all() -> &'static [&'static VolumeFormat] {
    &FORMATS
}

/// The format of scene key `key`.
pub fn by_key(key: &str) -> Option<&'static VolumeFormat> {
    all().iter().copied().find(|f| f.key == key)
}

/// The format of `path` by its extension (the longest that matches), raw
/// files included.
pub fn of_path(path: &Path) -> Option<&'static VolumeFormat> {
    let name = path.file_name()?.to_str()?.to_ascii_lowercase();
    (all().iter().copied())
        .flat_map(|f| f.extensions.iter().map(move |e| (e, f)))
        .filter(|(e, _)| name.ends_with(*e) && name.len() > e.len())
        .max_by_key(|(e, _)| e.len())
        .map(|(_, f)| f)
}

/// The format `path`'s extension alone tells (not raw files, whose size
/// is given).
pub fn by_extension(path: &Path) -> Option<&'static VolumeFormat> {
    of_path(path).filter(|f| f.by_extension)
}

/// The extensions of the formats `keep` accepts, in listing order.
pub fn extensions(keep: impl Fn(&VolumeFormat) -> bool) -> Vec<&'static str> {
    (all().iter())
        .filter(|f| keep(f))
        .flat_map(|f| f.extensions.iter().copied())
        .collect()
}

/// "a, b or c".
pub fn or_list(items: &[&str]) -> String {
    match items.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// What "unknown volume format" messages expect: the extensions that tell
/// a format, then the others (`…, or .raw`).
pub fn expected_extensions() -> String {
    let told = or_list(&extensions(|f| f.by_extension));
    let given = extensions(|f| !f.by_extension);
    if given.is_empty() {
        told
    } else {
        format!("{told}, or {}", given.join(", "))
    }
}

//! `fogbank convert IN -o OUT`: between the scene formats fogbank reads
//! (pbrt-v4, Mitsuba 3 XML, its own TOML) and those it writes (TOML always,
//! Mitsuba XML for what Mitsuba can express), and between volume formats
//! (`.vdb`, `.nvdb`, `.vol`, NIfTI, NRRD → `.vdb`/`.nvdb`). Both files'
//! kinds are told by their extensions:
//!
//! | in | out | how |
//! |---|---|---|
//! | `.pbrt`, `.xml`, `.toml` | `.toml` | [`scene_toml`]: the scene as fogbank reads it, its files named relative to OUT's folder inside it and absolute elsewhere, in-memory arrays written as `.vol` |
//! | `.pbrt`, `.xml`, `.toml` | `.xml` | [`mitsuba_writer`]: Mitsuba 3 XML, refusing or listing what Mitsuba cannot express |
//! | `.pbrt`, `.xml`, `.toml` | `.vdb`, `.nvdb` | a medium's grid, as `fogbank export` writes it |
//! | `.vdb`, `.nvdb`, `.vol`, `.nii`, `.nii.gz`, `.hdr`, `.nrrd`, `.nhdr` | `.vdb`, `.nvdb` | [`volume`]: one grid, every active voxel kept |
//!
//! A scene converted to TOML parses to the same [`SceneDesc`](fogbank_render::SceneDesc)
//! as its source, so it renders the same image bit for bit.

mod arrays;
pub mod mitsuba_writer;
mod output;
pub mod scene_toml;
pub mod volume;

pub use output::{ConvertOptions, Converted};

use crate::load::SceneFormat;
use fogbank_render::error::SceneError;
use fogbank_volume::formats;
use std::path::Path;
use std::sync::LazyLock;

/// What a file is, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    Scene(SceneFormat),
    /// A volume file: the key of its format
    /// (`fogbank_volume::formats`: `vdb`, `nvdb`, `vol`, `nifti`,
    /// `nrrd`).
    Volume(&'static str),
}

/// Every file kind fogbank reads, by extension: the scene formats, then
/// the volume formats of `fogbank_volume::formats` that their
/// extension tells (raw volumes, `.raw`, are read only with their
/// dimensions given: `info --dims`, a scene's `raw` key). [`FileKind::of`],
/// the error messages and the commands' help texts follow it (the help
/// texts and the guide are checked against it by a test).
pub static FORMATS: LazyLock<Vec<(&'static str, FileKind)>> = LazyLock::new(|| {
    let scenes = [
        (".toml", FileKind::Scene(SceneFormat::Toml)),
        (".xml", FileKind::Scene(SceneFormat::MitsubaXml)),
        (".pbrt", FileKind::Scene(SceneFormat::Pbrt)),
    ];
    let volumes = (formats::all().iter())
        .filter(|f| f.by_extension)
        .flat_map(|f| f.extensions.iter().map(|&e| (e, FileKind::Volume(f.key))));
    scenes.into_iter().chain(volumes).collect()
});

impl FileKind {
    /// The kind of `path`, or `None` for an extension fogbank does not know.
    pub fn of(path: &Path) -> Option<FileKind> {
        let name = path.file_name()?.to_str()?.to_ascii_lowercase();
        FORMATS
            .iter()
            .filter(|(ext, _)| name.ends_with(ext) && name.len() > ext.len())
            .max_by_key(|(ext, _)| ext.len())
            .map(|&(_, kind)| kind)
    }

    pub fn is_scene(self) -> bool {
        matches!(self, FileKind::Scene(_))
    }
}

/// The extensions of the kinds `keep` accepts, as "a, b or c".
pub fn extensions(keep: impl Fn(FileKind) -> bool) -> String {
    let list: Vec<&str> = FORMATS
        .iter()
        .filter(|&&(_, k)| keep(k))
        .map(|&(e, _)| e)
        .collect();
    formats::or_list(&list)
}

/// Every extension, scenes then volumes.
fn known() -> String {
    format!(
        "{} (scenes); {} (volumes)",
        extensions(FileKind::is_scene),
        extensions(|k| !k.is_scene())
    )
}

/// Converts `input` to `output`, both told by their extensions (see the
/// module table).
pub fn convert(
    input: &Path,
    output: &Path,
    options: &ConvertOptions,
) -> Result<Converted, SceneError> {
    let kind = |p: &Path, role: &str| {
        FileKind::of(p).ok_or_else(|| {
            SceneError(format!(
                "{}: the {role}'s extension is not one fogbank converts ({})",
                p.display(),
                known()
            ))
        })
    };
    let (from, to) = (kind(input, "input")?, kind(output, "output")?);
    if !input.is_file() {
        return Err(SceneError(format!("{}: no such file", input.display())));
    }
    if output.canonicalize().ok() == input.canonicalize().ok() {
        return Err(SceneError(format!(
            "{}: the output would overwrite the input",
            output.display()
        )));
    }
    match (from, to) {
        (FileKind::Scene(_), FileKind::Scene(SceneFormat::Toml)) => {
            scene_toml::convert(input, output)
        }
        (FileKind::Scene(_), FileKind::Scene(SceneFormat::MitsubaXml)) => {
            mitsuba_writer::convert(input, output)
        }
        (FileKind::Scene(_), FileKind::Volume(v)) if writes(v) => {
            volume::from_scene(input, output, options)
        }
        (FileKind::Volume(key), FileKind::Volume(v)) if writes(v) => {
            volume::convert(input, key, output, options)
        }
        (_, FileKind::Scene(SceneFormat::Pbrt)) => Err(SceneError(format!(
            "{}: fogbank reads pbrt-v4 scenes but does not write them (write .toml or .xml)",
            output.display()
        ))),
        (FileKind::Volume(_), FileKind::Scene(_)) => Err(SceneError(format!(
            "{}: a volume file converts to a volume file ({}), not a scene",
            output.display(),
            written()
        ))),
        (_, FileKind::Volume(_)) => Err(SceneError(format!(
            "{}: volumes are written as {} only",
            output.display(),
            written()
        ))),
    }
}

/// Whether fogbank writes volume format `key`.
fn writes(key: &str) -> bool {
    formats::by_key(key).is_some_and(|f| f.write.is_some())
}

/// The extensions of the volume formats fogbank writes (".vdb or .nvdb").
fn written() -> String {
    formats::or_list(&formats::extensions(|f| f.write.is_some()))
}

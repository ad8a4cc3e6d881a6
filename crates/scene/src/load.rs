//! Scene files of every format fogbank reads, told by their extension:
//! fogbank's TOML schema ([`fogbank_render::scene`]), Mitsuba 3 XML
//! ([`crate::mitsuba`]) and pbrt-v4 ([`crate::pbrt`]), the last two
//! converted into the schema. Every front end loads files through
//! [`read_scene_source`], so a format added here is reachable from the
//! command, the viewer and Python alike.

use fogbank_render::error::SceneError;
use fogbank_render::scene::{parse_scene, Scene, DEFAULT_SCENE};
use std::path::{Path, PathBuf};

/// Loads a scene file (or the built-in scene when `path` is `None`).
pub fn load_scene(path: Option<&Path>, overrides: &[String]) -> Result<Scene, SceneError> {
    load_scene_or(path, DEFAULT_SCENE, overrides)
}

/// A scene file read as fogbank's TOML schema: its text, the name its
/// messages use and the folder its relative file names resolve against.
#[derive(Clone, Debug)]
pub struct SceneSource {
    pub text: String,
    pub origin: String,
    pub base: PathBuf,
}

/// The formats a scene file can be in, told by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneFormat {
    /// fogbank's own schema (anything not named below).
    Toml,
    /// A Mitsuba 3 scene (`.xml`).
    MitsubaXml,
    /// A pbrt-v4 scene (`.pbrt`).
    Pbrt,
}

impl SceneFormat {
    pub fn of(path: &Path) -> SceneFormat {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ext.eq_ignore_ascii_case("xml") {
            SceneFormat::MitsubaXml
        } else if ext.eq_ignore_ascii_case("pbrt") {
            SceneFormat::Pbrt
        } else {
            SceneFormat::Toml
        }
    }

    /// Whether the format has named defaults a loader may override
    /// (Mitsuba's `<default>` and `-D name=value`).
    pub fn takes_defines(self) -> bool {
        self == SceneFormat::MitsubaXml
    }
}

/// Reads a scene file of any format fogbank reads, by its extension:
/// `.xml` is a Mitsuba 3 scene (with `defines` overriding its
/// `<default>`s, Mitsuba's `-D`) and `.pbrt` a pbrt-v4 scene, converted
/// with their file names made absolute; anything else is fogbank's TOML.
/// Every front end loads files through this, so a format added here is
/// reachable from the command, the viewer and Python alike.
pub fn read_scene_source(
    path: &Path,
    defines: &[(String, String)],
) -> Result<SceneSource, SceneError> {
    let origin = path.display().to_string();
    let format = SceneFormat::of(path);
    if format == SceneFormat::MitsubaXml {
        let doc = crate::mitsuba::load_xml(path, defines)?;
        let text = toml::to_string(&doc).map_err(|e| SceneError(format!("{origin}: {e}")))?;
        return Ok(SceneSource {
            text,
            origin,
            base: PathBuf::new(),
        });
    }
    if format == SceneFormat::Pbrt && defines.is_empty() {
        let doc = crate::pbrt::load_pbrt(path)?;
        let text = toml::to_string(&doc).map_err(|e| SceneError(format!("{origin}: {e}")))?;
        return Ok(SceneSource {
            text,
            origin,
            base: PathBuf::new(),
        });
    }
    if let Some((name, _)) = defines.first() {
        return Err(SceneError(format!(
            "{origin}: define {name:?}: only Mitsuba XML scenes have defaults to override; set keys with dotted overrides"
        )));
    }
    let text = std::fs::read_to_string(path).map_err(|e| SceneError(format!("{origin}: {e}")))?;
    Ok(SceneSource {
        text,
        origin,
        base: path.parent().map(Path::to_path_buf).unwrap_or_default(),
    })
}

/// Loads a scene file, or the scene text `builtin` when `path` is `None`.
pub fn load_scene_or(
    path: Option<&Path>,
    builtin: &str,
    overrides: &[String],
) -> Result<Scene, SceneError> {
    let source = match path {
        Some(p) => read_scene_source(p, &[])?,
        None => SceneSource {
            text: builtin.to_string(),
            origin: "built-in scene".to_string(),
            base: PathBuf::from("."),
        },
    };
    let desc = parse_scene(&source.text, &source.origin, overrides)?;
    Scene::build(desc, &source.base)
}

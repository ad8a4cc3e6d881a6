//! A scene of any format fogbank reads written as fogbank's TOML: the
//! document [`read_scene_source`] makes of it, checked by parsing it as a
//! [`SceneDesc`], with its relative file names rewritten so the file loads
//! from its new folder ([`rebase_paths`]: absolute unless the folder is the
//! same), and the files inside that folder named relative to it. pbrt-v4 and Mitsuba sources already name their files absolutely;
//! in-memory arrays (pbrt's uniform grids) become `.vol` files beside it
//! (`arrays`). Otherwise the written text parses to the same
//! [`SceneDesc`] as the source, so it renders the same image.

use super::arrays::write_arrays;
use super::output::{write_file, Converted};
use crate::load::read_scene_source;
use fogbank_render::error::SceneError;
use fogbank_render::rebase::{is_file_key, rebase_paths};
use fogbank_render::scene::{parse_scene, SceneDesc};
use std::path::Path;

/// The scene `input` as fogbank TOML text for the file `output`, and its
/// description; its in-memory arrays are written beside `output`
/// (`arrays`).
pub fn scene_toml(input: &Path, output: &Path) -> Result<(String, SceneDesc), SceneError> {
    let source = read_scene_source(input, &[])?;
    let desc = parse_scene(&source.text, &source.origin, &[])?;
    let mut doc: toml::Value =
        toml::from_str(&source.text).map_err(|e| SceneError(format!("{}: {e}", source.origin)))?;
    let out_dir = folder_of(output);
    rebase_paths(&mut doc, &source.base, out_dir);
    if let Ok(dir) = out_dir.canonicalize() {
        relative_inside(&mut doc, &dir);
    }
    let stem = output
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene");
    write_arrays(&mut doc, out_dir, stem)?;
    let text = toml::to_string(&doc).map_err(|e| SceneError(format!("{}: {e}", source.origin)))?;
    Ok((text, desc))
}

/// Makes the absolute file names of `doc` that lie inside the folder
/// `dir` (canonical) relative to it, so the scene moves with its files.
fn relative_inside(v: &mut toml::Value, dir: &Path) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t.iter_mut() {
                match x {
                    toml::Value::String(s) if is_file_key(k) => {
                        let p = Path::new(s.as_str());
                        let p = p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
                        if let Ok(r) = p.strip_prefix(dir) {
                            if p.is_absolute() && !r.as_os_str().is_empty() {
                                *s = r.display().to_string();
                            }
                        }
                    }
                    _ => relative_inside(x, dir),
                }
            }
        }
        toml::Value::Array(a) => a.iter_mut().for_each(|x| relative_inside(x, dir)),
        _ => {}
    }
}

/// The folder a file `out` is written in (`.` for a bare name).
pub fn folder_of(out: &Path) -> &Path {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Converts the scene `input` to the TOML file `output`.
pub fn convert(input: &Path, output: &Path) -> Result<Converted, SceneError> {
    let (text, desc) = scene_toml(input, output)?;
    let header = format!(
        "# Converted by `fogbank convert` from {}\n\n",
        input.display()
    );
    write_file(output, format!("{header}{text}").as_bytes())?;
    Ok(Converted {
        summary: format!(
            "{}: {} media, {} lights, {} shapes",
            output.display(),
            desc.media.len(),
            desc.lights.len(),
            desc.shapes.len()
        ),
        notes: Vec::new(),
    })
}

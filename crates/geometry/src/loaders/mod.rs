//! Mesh files: Wavefront OBJ (through `tobj`) and PLY, ASCII and binary
//! (through `ply-rs-bw`). Errors name the file and, where the format has
//! lines, the line at fault; nothing is allocated from a count the file
//! claims before the data behind it is read.

pub mod obj;
pub mod ply;

use crate::mesh::TriangleMesh;
use std::path::Path;

/// Loads `path` by its extension (`.obj`, `.ply`).
pub fn load_mesh(path: &Path) -> Result<TriangleMesh, String> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .as_deref()
    {
        Some("obj") => obj::load(path),
        Some("ply") => ply::load(path),
        _ => Err(format!(
            "{}: unknown mesh format (use .obj or .ply)",
            path.display()
        )),
    }
}

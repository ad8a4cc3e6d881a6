//! The grid a scene gets from a file of several (OpenVDB, NanoVDB) when it
//! names none: the conventional name first (`density`; for vectors `vel`,
//! `v`, `velocity`, as Houdini and Blender write them), else the first
//! grid of the wanted kind.

use crate::error::{Result, VolumeError};
use std::path::Path;

/// The names tried first for grids of `components` floats per voxel, best
/// first.
pub fn default_names(components: usize) -> &'static [&'static str] {
    if components == 3 {
        &["vel", "v", "velocity"]
    } else {
        &["density"]
    }
}

/// A grid as a file's header lists it.
pub trait ListedGrid {
    /// Its name, as the defaults are matched against.
    fn grid_name(&self) -> &str;
    /// Its name and type for messages, e.g. `` `density` (float) ``.
    fn describe(&self) -> String;
}

/// The grid to read from `entries` when none is named: the first of
/// [`default_names`] that `fits`, else the first that `fits`. Otherwise an
/// error naming the `wanted` kind and every grid of the file.
pub fn pick_default<'e, E: ListedGrid>(
    path: &Path,
    entries: &'e [E],
    components: usize,
    fits: impl Fn(&E) -> bool,
    wanted: &str,
) -> Result<&'e E> {
    let fitting = || entries.iter().filter(|e| fits(e));
    let pick = default_names(components)
        .iter()
        .find_map(|n| fitting().find(|e| e.grid_name() == *n))
        .or_else(|| fitting().next());
    pick.ok_or_else(|| {
        let all: Vec<String> = entries.iter().map(ListedGrid::describe).collect();
        let listed = if all.is_empty() {
            "none".to_string()
        } else {
            all.join(", ")
        };
        VolumeError::format(
            path,
            format!("no {wanted} grid to read (grids in file: {listed})"),
        )
    })
}

//! Mitsuba 3 XML scenes (issue 23): `fogbank render scene.xml` reads a
//! scene written for Mitsuba and renders it as Mitsuba's `volpath` would.
//!
//! The subset: `include`, `path`, `default` and `$name` substitution,
//! `ref`/`id`; `transform` (`lookat`, `translate`, `rotate`, `scale`,
//! `matrix`); `sensor` perspective (`fov`, `fov_axis`; clip planes only
//! at their defaults, fogbank does not clip), `film` hdrfilm with a box
//! `rfilter`, `sampler` independent; `integrator` volpath, volpathmis and a
//! `moment` around one (fogbank always writes the variance); `medium`
//! homogeneous and heterogeneous with `gridvolume` (`.vol`,
//! `use_grid_bbox`) or `constvolume`, `phase` isotropic and hg; `rgb` and
//! constant `spectrum` values; shapes obj, ply, rectangle, cube, sphere,
//! disk (the last two analytic); the BSDFs of
//! `world::surfaces::material`; `checkerboard` and `bitmap` textures; emitters area,
//! constant, envmap, point, directional, spot.
//!
//! Anything else is refused with its file, line, tag and plugin name, and
//! so is any parameter fogbank would otherwise ignore. Conventions that
//! differ: Mitsuba's `max_depth` counts path segments (fogbank's = it − 1;
//! −1 is unlimited); chromatic σ_t (RGB constants, 3-channel grids) is
//! fogbank's `sigma_t_scale = [r, g, b]` / `density_rgb`; Beckmann
//! roughness and spectral data are refused until fogbank has them.

mod bsdfs;
mod convert;
mod emitters;
mod media;
mod plugin;
mod shapes;
mod transform;
mod values;
mod xml;

use crate::error::SceneError;
use std::path::Path;

/// A Mitsuba XML file as a fogbank scene document (the TOML tables a
/// scene file would hold); `defines` are `name=value` pairs that override
/// its `<default>`s (Mitsuba's `-D`).
pub fn load_xml(path: &Path, defines: &[(String, String)]) -> Result<toml::Table, SceneError> {
    let doc = xml::read(path, defines)?;
    convert::scene_table(&doc)
}

/// [`load_xml`] of XML text; `path` names it in messages and anchors its
/// relative file names (what the fuzz target drives).
pub fn load_xml_str(
    text: &str,
    path: &Path,
    defines: &[(String, String)],
) -> Result<toml::Table, SceneError> {
    let doc = xml::read_str(text, path, defines)?;
    convert::scene_table(&doc)
}

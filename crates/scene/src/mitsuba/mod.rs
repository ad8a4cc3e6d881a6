//! Mitsuba 3 XML scenes: `fogbank render scene.xml` reads a scene written
//! for Mitsuba as Mitsuba reads it and renders it as Mitsuba's `volpath`
//! would.
//!
//! The subset: `include`, `path`, `default` and `$name` substitution,
//! `ref`/`id`, with file names resolved as Mitsuba's `FileResolver` does
//! (the top-level scene's folder and its `<path>`s; an include also beside
//! the file that includes it, see [`xml`]); `transform` (`lookat`,
//! `translate`, `rotate`, `scale`, `matrix`); `sensor` perspective (`fov`
//! and `fov_axis`, or `focal_length`, default 50 mm, as Mitsuba's
//! `parse_fov`; `near_clip` and `far_clip`, default 0.01 and 10⁴: rays
//! start on the near plane and the first segment ends on the far one; a
//! mirroring `to_world` is fogbank's camera `mirror`),
//! `film` hdrfilm with a box `rfilter`, `sampler` independent; `integrator`
//! volpath, volpathmis and a `moment` around one (fogbank always writes the
//! variance); `medium` homogeneous and heterogeneous with `gridvolume`
//! (`.vol`, `use_grid_bbox`) or `constvolume`, `phase` isotropic and hg;
//! `rgb`, `float` and `spectrum` values (constants and wavelength:value
//! pairs, converted to RGB as Mitsuba's RGB variants convert them,
//! [`fogbank_image::spectrum`]); shapes obj, ply, rectangle, cube, sphere,
//! disk (the last two analytic); the BSDFs of `world::surfaces::bsdf_desc`
//! with Mitsuba's default Beckmann or GGX microfacets and either sampling of
//! normals; `checkerboard` and `bitmap` textures; emitters area, constant,
//! envmap, point, directional, spot.
//!
//! Anything else is refused with its file, line, tag and plugin name, and
//! so is any parameter fogbank would otherwise ignore. A heterogeneous
//! medium exists, as in Mitsuba, only inside its σ_t volume's box (the unit
//! cube under the volume's `to_world`, for a `constvolume` too). Conventions
//! that differ: Mitsuba's `max_depth` counts path segments (fogbank's = it
//! − 1; −1 is unlimited); chromatic σ_t (RGB constants, 3-channel grids) is
//! fogbank's `sigma_t_scale = [r, g, b]` / `density_rgb`. `<blackbody>` is
//! refused, as Mitsuba's RGB variants refuse it.

mod bsdfs;
mod convert;
mod emitters;
mod media;
mod plugin;
mod shapes;
mod transform;
mod values;
mod xml;

use fogbank_render::error::SceneError;
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

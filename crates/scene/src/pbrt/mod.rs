//! pbrt-v4 scenes: `fogbank render scene.pbrt` reads a scene written for
//! pbrt-v4 and renders it as pbrt's `volpath` would, within what fogbank's
//! scene description holds.
//!
//! Reading: [`tokenizer`] (comments, strings, brackets), [`cursor`]
//! (`Include` splices tokens, so a statement may continue across the end
//! of an included file; `Import` is read the same way, in the world block
//! only; relative names resolve beside the including file, then beside the
//! top-level file), [`params`] (typed parameter lists; an unused parameter
//! is an error, as in pbrt), [`state`] (transforms and attributes) and
//! [`interpret`] (the statements). Every error names the file and line.
//!
//! Mapping, each module documenting its own: [`options`] (camera, film,
//! sensor, sampler, filter, integrator), [`media`] (with [`rgbgrid`],
//! [`cloud`] and the in-memory arrays of [`grids`]), [`lights`] (with
//! [`envlight`] for image infinite lights), [`shapes`] (with [`meshes`]),
//! [`materials`] and [`spectra`]; [`convert`] puts them together.
//!
//! Conventions that differ, and how they are met:
//! - pbrt's camera frame is left-handed; fogbank's camera gets
//!   `mirror = true` so the image is pbrt's, not its mirror image.
//! - pbrt's media fill space wherever a `MediumInterface` puts them;
//!   fogbank's are bounded: a homogeneous medium becomes a constant grid over
//!   the box of the shapes it is inside of, or the scene's box when it is an
//!   outside or the camera's medium.
//! - pbrt renders spectrally; fogbank in linear sRGB ([`spectra`]).
//! - What fogbank reads from files but pbrt gives inline or in its own
//!   layout (inline meshes, equal-area octahedral environment maps) is
//!   written into cache folders in the system's temporary folder
//!   (`fogbank-pbrt-meshes`, `fogbank-pbrt-envmaps`), files named by a hash
//!   of what they hold, so reading a scene again reuses them.
//!
//! Approximations print a notice once: the pixel filter, the sampler,
//! named spectral sensors (the CIE 1931 observer), `whitebalance`,
//! `maxcomponentvalue`, the imaging ratio (as `render.exposure`),
//! `coateddiffuse`, named glasses (their d-line index), unbounded
//! homogeneous media, `cloud` media baked into a grid ([`cloud`]),
//! `rgbgrid`'s albedo interpolated per voxel ([`rgbgrid`]), image infinite
//! lights resampled to lat-long ([`envlight`]), curved bilinear patches
//! and ellipsoids (non-uniformly scaled spheres) tessellated ([`meshes`]).
//! Anything fogbank cannot express is refused with its file and line:
//! textures, motion (`ActiveTransform`), lenses, portal infinite lights,
//! goniometric and projection lights, emitting `uniformgrid`s, partial
//! quadrics, shading tangents (`S`) on inline meshes, and integrators other
//! than `volpath` (and `path` without media).

pub mod cloud;
pub mod convert;
pub mod cursor;
pub mod envlight;
pub mod grids;
pub mod interpret;
pub mod lights;
pub mod materials;
pub mod media;
pub mod meshes;
pub mod options;
pub mod params;
pub mod rgbgrid;
pub mod shapes;
pub mod spectra;
pub mod state;
pub mod tables;
pub mod tokenizer;
pub mod warnings;

use fogbank_render::error::SceneError;
use std::path::Path;

/// A pbrt-v4 file as a fogbank scene document (the TOML tables a scene
/// file would hold), its file names made absolute.
pub fn load_pbrt(path: &Path) -> Result<toml::Table, SceneError> {
    if path.extension().is_some_and(|e| e == "gz") {
        return Err(SceneError(format!(
            "{}: gzip-compressed scene files are not supported; decompress it",
            path.display()
        )));
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError(format!("{}: {e}", path.display())))?;
    load_pbrt_str(&text, path)
}

/// [`load_pbrt`] of pbrt text; `path` names it in messages and anchors its
/// relative file names.
pub fn load_pbrt_str(text: &str, path: &Path) -> Result<toml::Table, SceneError> {
    let parsed = interpret::interpret(text, path)?;
    convert::scene_table(parsed)
}

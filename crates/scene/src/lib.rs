//! Scene files: every format fogbank reads, converted into the scene
//! schema of `fogbank-render` (its TOML), and every format it writes.
//!
//! Modules in layers, each importing only those before it: `mitsuba`
//! (Mitsuba 3 XML as Mitsuba reads it) and `pbrt` (pbrt-v4) → `load` (a
//! scene file of any format, told by its extension; the one loader every
//! front end calls) → `export` (a built medium's grids written as OpenVDB
//! or NanoVDB) → `convert` (`fogbank convert`: scene to TOML or Mitsuba
//! XML, volume to OpenVDB or NanoVDB).

pub mod convert;
pub mod export;
pub mod load;
pub mod mitsuba;
pub mod pbrt;

pub use load::{load_scene, load_scene_or, read_scene_source, SceneFormat, SceneSource};

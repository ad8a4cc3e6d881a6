//! Scenes, cameras, lights, integrators and the progressive render loop.
//!
//! Modules in layers, each importing only those before it:
//! `error`, `params`, `overrides`, `rebase` (a scene's file names written
//! for another folder) and `shard` (which part of a render one shard does)
//! → `world` (camera, film, media and their fields, emission, phase) and
//! `lights` →
//! `integrators` (the shared pieces in `integrators::shared`, one file or
//! folder per integrator, registered in `integrators/mod.rs`) →
//! `animation` (keyframes, per-frame files) → `scene` (description, world
//! and integrator; the TOML schema every scene format is read into) →
//! `render` (the progressive loop); `desc` re-exports every description.
//! Above this crate: scene files of other formats, conversion and the
//! writers (`fogbank-scene`), a shard's partial result and the merge
//! (`fogbank-partial`).

pub mod animation;
pub mod desc;
pub mod error;
pub mod integrators;
pub mod lights;
pub mod overrides;
pub mod params;
pub mod rebase;
pub mod render;
pub mod scene;
pub mod shard;
pub mod world;

pub use error::SceneError;
pub use render::{
    render, render_observed, render_piece, render_piece_observed, Progress, RenderOptions,
    RenderResult,
};
pub use scene::{parse_scene, Scene, SceneDesc, DEFAULT_SCENE, TRANSMITTANCE_SCENE};
pub use world::film::Film;
pub use world::World;

#[cfg(test)]
mod registry_test;

//! Scenes, cameras, lights, integrators and the progressive render loop.

pub mod blackbody;
pub mod camera;
pub mod desc;
pub mod emission;
pub mod field;
pub mod film;
pub mod integrators;
pub mod lights;
pub mod phase;
pub mod render;
pub mod scene;

pub use desc::{SceneDesc, SceneError, DEFAULT_SCENE};
pub use film::Film;
pub use render::{render, render_observed, Progress, RenderOptions, RenderResult};
pub use scene::{load_scene, parse_scene, Scene};

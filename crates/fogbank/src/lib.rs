//! fogbank's library entry point: what every front end — the `fogbank`
//! command, the viewer, the Python package — calls to render. A front end
//! loads a [`Scene`] ([`load_scene`]), picks a [`Renderer`] (the CPU's
//! worker pool or a GPU), describes the work as a [`RenderJob`] (samples or
//! a time budget, a shard) and gets a [`Rendered`] film back, with what to
//! write ([`output`]) and report ([`stats::render_stats`]); animated scenes
//! render as a [`frames::FrameSequence`]; an estimator's per-pixel
//! statistics over independent frames are a [`study::StatsJob`]; estimators
//! on the caller's own rays are [`rays`].
//! Presentation (progress bars,
//! notebooks, windows) stays with the front ends.
//!
//! Modules in layers, each importing only those before it: `error` (errors with a
//! kind each front end maps to its own) and `shard_run` (the record of where and how a
//! shard ran, kept in its partial result) → `renderer` (the CPU's worker pool or a GPU,
//! behind one call) → `job` (samples per pixel or a time budget, a shard, and the checks
//! every front end shares), `compare` (`fogbank compare`'s metrics of a test image
//! against a reference), `stats`, `rays` and `output` → `frames` and `study`.

pub mod compare;
pub mod error;
pub mod frames;
pub mod job;
pub mod output;
pub mod rays;
pub mod renderer;
pub mod shard_run;
pub mod stats;
pub mod study;

pub use error::{Error, ErrorKind};
pub use fogbank_render::shard::{Piece, Shard, ShardMode};
pub use fogbank_render::{load_scene, parse_scene, Film, Progress, RenderOptions, Scene};
pub use job::RenderJob;
pub use renderer::{Device, Rendered, Renderer};

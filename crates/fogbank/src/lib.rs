//! fogbank's library entry point: what every front end — the `fogbank`
//! command, the viewer, the Python package — calls to render. A front end
//! loads a [`Scene`] ([`load_scene`]), picks a [`Renderer`] (the CPU's
//! worker pool or a GPU), describes the work as a [`RenderJob`] (samples or
//! a time budget, a shard) and gets a [`Rendered`] film back, with what to
//! write ([`output`]) and report ([`stats::render_stats`]); animated scenes
//! render as a [`frames::FrameSequence`]; an estimator's per-pixel
//! statistics over independent frames are a [`study::StatsJob`]; estimators
//! on the caller's own rays are [`rays`]; the estimators' cost and accuracy
//! side by side is [`bench`]; what a volume file holds is [`info`], and a
//! grid from an array or a file is [`volumes`]; what a merge of shards
//! reports is [`merged`]. What a front end shows or edits comes from here
//! too: the scene description and the integrators' registry ([`desc`]),
//! tone mapping and image files ([`image`]), scene and volume conversion
//! ([`convert`], [`export`]). Presentation (progress bars, notebooks,
//! windows) stays with the front ends, and the papers' experiments live
//! above, in `fogbank-experiments`.
//!
//! Modules in layers, each importing only those before it: `desc`, `image`
//! and `testing` (re-exports of the inner crates' public types and test
//! helpers), `error` (errors with a kind each front end maps to its own)
//! and `shard_run` (the record of where and how a shard ran, kept in its
//! partial result) → `renderer` (the CPU's worker pool or a GPU, behind one
//! call) → `job` (samples per pixel or a time budget, a shard, and the
//! checks every front end shares), `compare` (`fogbank compare`'s metrics
//! of a test image against a reference), `info`, `volumes`, `stats`,
//! `rays` and `output` → `merged`, `bench`, `frames` and `study`.

pub mod bench;
pub mod compare;
pub mod desc;
pub mod error;
pub mod frames;
pub mod image;
pub mod info;
pub mod job;
pub mod merged;
pub mod output;
pub mod rays;
pub mod renderer;
pub mod shard_run;
pub mod stats;
pub mod study;
pub mod testing;
pub mod volumes;

pub use error::{Error, ErrorKind};
pub use fogbank_estimators::Estimator;
pub use fogbank_eval::report;
pub use fogbank_gpu::Gpu;
pub use fogbank_partial::{merge, partial};
pub use fogbank_render::shard::{Piece, Shard, ShardMode};
pub use fogbank_render::{
    parse_scene, Film, Progress, RenderOptions, Scene, SceneError, DEFAULT_SCENE,
    TRANSMITTANCE_SCENE,
};
pub use fogbank_scene::{
    convert, export, load_scene, load_scene_or, read_scene_source, SceneFormat, SceneSource,
};
pub use job::RenderJob;
pub use renderer::{Device, Rendered, Renderer};

//! What every paper's experiments share, in one place:
//!
//! - `writer`: [`Writer`], where an experiment's files go (CSV, PNG, plots,
//!   text), recorded for the report;
//! - `trials`: deterministic parallel Monte Carlo (chunked PCG32 streams
//!   merged in order) and running moments;
//! - `protocol`: rendering frames against an offline reference — scene
//!   building with overrides, references and their noise floors, MSE,
//!   independent frames, frames raced within a time budget;
//! - `clock`: the wall-clock time of one piece of work;
//! - `timing`: device time per sample on a GPU (median of renders after a
//!   warm-up);
//! - `scene_edit`: [`SceneText`], edits of a shipped scene that fail when
//!   they miss;
//! - `fit`: [`log_log_fit`], power laws as straight lines in log-log space.

mod clock;
mod fit;
pub mod protocol;
mod scene_edit;
pub mod timing;
pub mod trials;
mod writer;

pub use fit::log_log_fit;
pub use scene_edit::SceneText;
pub use writer::Writer;

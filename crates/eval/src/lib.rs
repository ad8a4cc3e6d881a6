//! Evaluation tools: the measurements every comparison in fogbank uses.
//!
//! Image I/O and the image metrics live in `fogbank-image` and are
//! re-exported here as [`image_io`] and [`metrics`].

pub mod backend;
pub mod converge;
pub mod denoise;
pub mod experiments;
pub mod frame_stats;
pub mod maps;
pub mod plot;
pub mod report;

pub use backend::Backend;
pub use fogbank_image::{image_io, metrics};
pub use frame_stats::{exact_reference, frame_stats, transmittance_stats, FrameStats, Summary};

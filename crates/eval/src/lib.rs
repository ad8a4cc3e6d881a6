//! Evaluation tools: the measurements every comparison in fogbank uses.

pub mod converge;
pub mod experiments;
pub mod frame_stats;
pub mod image_io;
pub mod maps;
pub mod metrics;
pub mod plot;
pub mod report;

pub use frame_stats::{exact_reference, frame_stats, transmittance_stats, FrameStats, Summary};

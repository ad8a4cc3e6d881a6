//! Evaluation tools: the measurements every comparison in fogbank uses.

pub mod converge;
pub mod frame_stats;
pub mod report;

pub use frame_stats::{exact_reference, frame_stats, transmittance_stats, FrameStats, Summary};

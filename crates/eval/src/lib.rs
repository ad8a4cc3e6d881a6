//! The studies every user runs: the measurements each comparison in
//! fogbank uses. The papers' experiments built on them live above, in
//! `fogbank-experiments`.
//!
//! Image I/O and the image metrics live in `fogbank-image` and are
//! re-exported here as [`image_io`] and [`metrics`].
//!
//! Modules in layers, each importing only those before it:
//! - `backend` (where a study renders: the CPU reference or the wgpu backend),
//!   `median` (of repeated timings), `plot` (line plots, histograms and heat maps in panels, written as SVG and PNG)
//!   and `report` (`fogbank report`: one offline HTML page of the runs below a
//!   folder);
//! - `frame_stats` (per-pixel mean, single-frame std and bias over K independent 1-spp
//!   frames, Peters 2025 §6.1) and `converge` (equal-time curves: MSE against a reference
//!   as a function of render time);
//! - `maps` (false-colour maps of per-pixel statistics with a colour bar, Peters 2025
//!   Figs. 8 and 10).

pub mod backend;
pub mod converge;
pub mod frame_stats;
pub mod maps;
pub mod median;
pub mod plot;
pub mod report;

pub use backend::Backend;
pub use fogbank_image::{image_io, metrics};
pub use frame_stats::{exact_reference, frame_stats, transmittance_stats, FrameStats, Summary};

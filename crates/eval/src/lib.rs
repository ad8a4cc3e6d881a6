//! Evaluation tools: the measurements every comparison in fogbank uses.
//!
//! Image I/O and the image metrics live in `fogbank-image` and are
//! re-exported here as [`image_io`] and [`metrics`].
//!
//! Modules in layers, each importing only those before it:
//! - `backend` (where an experiment renders: the CPU reference or the wgpu backend),
//!   `plot` (line plots, histograms and heat maps in panels, written as SVG and PNG),
//!   `denoise` (an external denoiser, Intel Open Image Denoise by default, run as a
//!   command) and `report` (`fogbank report`: one offline HTML page of the runs below a
//!   folder);
//! - `frame_stats` (per-pixel mean, single-frame std and bias over K independent 1-spp
//!   frames, Peters 2025 §6.1) and `converge` (equal-time curves: MSE against a reference
//!   as a function of render time);
//! - `maps` (false-colour maps of per-pixel statistics with a colour bar, Peters 2025
//!   Figs. 8 and 10) and `experiments` (the papers' figures and tables, one folder per
//!   paper, each writing CSV, plots and a `summary.md`).

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

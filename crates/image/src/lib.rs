//! Images: reading and writing fogbank's EXR (colour plus a `variance`
//! layer) and sRGB PNG, and the metrics that compare a test image with a
//! reference. Depends on no rendering crate, so every layer's tests can use
//! it.
//!
//! Modules in layers, each importing only those before it: `tonemap` (display
//! transforms: an exposure, then the `linear`, `aces` or `agx` curve to sRGB) and
//! `spectrum` (spectra as linear sRGB, as Mitsuba 3's RGB variants read them) →
//! `image_io` (EXR with a `variance` layer and sRGB PNG, read and written; a malformed
//! file is an error, never a panic) → `metrics` (a test image against a reference).

pub mod image_io;
pub mod metrics;
pub mod spectrum;
pub mod tonemap;

pub use image_io::Image;
pub use tonemap::{luminance, ToneCurve, ToneMapping};

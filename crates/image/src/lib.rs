//! Images: reading and writing fogbank's EXR (colour plus a `variance`
//! layer) and sRGB PNG, and the metrics that compare a test image with a
//! reference. Depends on no rendering crate, so every layer's tests can use
//! it.

pub mod image_io;
pub mod metrics;
pub mod spectrum;
pub mod tonemap;

pub use image_io::Image;
pub use tonemap::{luminance, ToneCurve, ToneMapping};

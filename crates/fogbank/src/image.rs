//! What front ends do with images: tone mapping for display, and EXR and
//! PNG files.

pub use fogbank_image::image_io::{write_exr, write_png};
pub use fogbank_image::{luminance, ToneCurve, ToneMapping};

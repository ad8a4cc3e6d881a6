//! What front ends do with images: tone mapping for display, and EXR and
//! PNG files.

pub use fogbank_image::image_io::{encode_png, read_image, write_exr, write_png, Image};
pub use fogbank_image::{luminance, ToneCurve, ToneMapping};

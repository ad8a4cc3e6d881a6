//! A film as image files: the mean (non-finite pixels as 0) to EXR or PNG,
//! with the variance of the mean as an EXR layer; shared by `render`,
//! `merge` and frame sequences.

use fogbank_image::image_io::{write_exr, write_png};
use std::path::PathBuf;

/// What a film writes as an image.
pub struct FilmImage {
    /// The mean, non-finite pixels written as 0 (the film drops non-finite
    /// samples; this guards the divisions).
    pub rgb: Vec<[f32; 3]>,
    /// The variance of the mean, once every pixel has two samples.
    pub variance: Option<Vec<[f32; 3]>>,
    /// Pixels whose mean was not finite.
    pub bad_pixels: usize,
}

pub fn film_rgb(film: &fogbank_render::Film) -> FilmImage {
    let mean = film.mean();
    let bad_pixels = mean
        .iter()
        .filter(|p| p.iter().any(|c| !c.is_finite()))
        .count();
    let rgb = mean
        .into_iter()
        .map(|p| p.map(|c| if c.is_finite() { c } else { 0.0 }))
        .collect();
    let variance = (film.min_spp() > 1).then(|| film.variance_of_mean());
    FilmImage {
        rgb,
        variance,
        bad_pixels,
    }
}

/// Writes a film's mean to each output: EXR (linear, with a `variance`
/// layer once every pixel has two samples) or PNG (tone-mapped). Returns the
/// pixels whose mean was not finite (written as 0).
pub fn write_images(
    outputs: &[PathBuf],
    film: &fogbank_render::Film,
    tone: &fogbank_image::ToneMapping,
) -> Result<usize, Box<dyn std::error::Error>> {
    let img = film_rgb(film);
    for out in outputs {
        match out.extension().and_then(|e| e.to_str()) {
            Some("exr") => write_exr(
                out,
                film.width,
                film.height,
                &img.rgb,
                img.variance.as_deref(),
            )?,
            _ => write_png(out, film.width, film.height, &img.rgb, tone)?,
        }
    }
    Ok(img.bad_pixels)
}

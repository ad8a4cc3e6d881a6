//! A film as files: the mean (non-finite pixels as 0) to EXR or PNG, with
//! the variance of the mean as an EXR layer; and a shard's partial result.

use crate::error::Error;
use crate::renderer::Rendered;
use crate::shard_run;
use fogbank_image::image_io::{write_exr, write_png};
use fogbank_image::ToneMapping;
use fogbank_partial::partial::{Partial, PartialHeader};
use fogbank_render::shard::Shard;
use fogbank_render::{Film, Scene};
use std::path::{Path, PathBuf};

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

pub fn film_rgb(film: &Film) -> FilmImage {
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

/// Writes `rgb` (and `variance`, EXR only) of a `width`×`height` image to
/// `out`: EXR (linear) or PNG (tone-mapped by `tone`), by extension.
pub fn write_image(
    out: &Path,
    width: u32,
    height: u32,
    rgb: &[[f32; 3]],
    variance: Option<&[[f32; 3]]>,
    tone: &ToneMapping,
) -> Result<(), Error> {
    match out.extension().and_then(|e| e.to_str()) {
        Some("exr") => write_exr(out, width, height, rgb, variance),
        _ => write_png(out, width, height, rgb, tone),
    }
    .map_err(|e| Error::runtime(e.to_string()))
}

/// Writes a film's mean to each output. Returns the pixels whose mean was
/// not finite (written as 0).
pub fn write_images(outputs: &[PathBuf], film: &Film, tone: &ToneMapping) -> Result<usize, Error> {
    let img = film_rgb(film);
    for out in outputs {
        write_image(
            out,
            film.width,
            film.height,
            &img.rgb,
            img.variance.as_deref(),
            tone,
        )?;
    }
    Ok(img.bad_pixels)
}

/// Writes shard `shard`'s part of a render of `spp` samples as a partial
/// result at `out` (`frame`: the animation frame it belongs to), under
/// the scene's seed.
pub fn write_partial(
    out: &Path,
    scene: &Scene,
    spp: u32,
    shard: Shard,
    rendered: Rendered,
    threads: usize,
    frame: Option<u32>,
) -> Result<(), Error> {
    let seed = scene.desc.render.seed;
    let run = shard_run::run(shard, spp, rendered.seconds, threads);
    let mut header = PartialHeader::for_shard("render", scene, seed, spp, &rendered.film, run);
    header.identity.frame = frame;
    Partial {
        header,
        film: rendered.film,
        covered: None,
    }
    .write(out)
    .map_err(|e| Error::runtime(e.to_string()))
}

//! Image output: linear float EXR (colour plus a `variance` layer holding the
//! per-pixel variance of the mean) and tone-mapped sRGB PNG.

use exr::prelude::*;
use std::path::Path;

/// Writes R, G, B and, if given, `variance.R/G/B` as 32-bit float channels
/// of one part; OpenEXR tools and tev read the `variance.` prefix as a layer.
pub fn write_exr(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[[f32; 3]],
    variance: Option<&[[f32; 3]]>,
) -> std::result::Result<(), String> {
    let mut layers = vec![("", rgb.to_vec())];
    if let Some(v) = variance {
        layers.push(("variance", v.to_vec()));
    }
    write_exr_channels(path, width, height, &layers, None)
}

/// sRGB transfer function of a linear value clamped to [0, 1].
fn srgb8(v: f32) -> u8 {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[[f32; 3]],
    exposure: f32,
) -> std::result::Result<(), String> {
    let k = 2f32.powf(exposure);
    let bytes: Vec<u8> = rgb.iter().flat_map(|p| p.map(|c| srgb8(c * k))).collect();
    image::save_buffer(path, &bytes, width, height, image::ColorType::Rgb8)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes named RGB layers (`NAME.R/G/B`; plain `R/G/B` for an empty name)
/// and an optional scalar channel (`NAME.Y`) into one EXR part.
pub fn write_exr_channels(
    path: &Path,
    width: u32,
    height: u32,
    layers: &[(&str, Vec<[f32; 3]>)],
    scalar: Option<(&str, &[f32])>,
) -> std::result::Result<(), String> {
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    for (name, data) in layers {
        for (c, suffix) in ["R", "G", "B"].iter().enumerate() {
            let plane = FlatSamples::F32(data.iter().map(|p| p[c]).collect());
            let full = if name.is_empty() {
                suffix.to_string()
            } else {
                format!("{name}.{suffix}")
            };
            channels.push(AnyChannel::new(full.as_str(), plane));
        }
    }
    if let Some((name, data)) = scalar {
        channels.push(AnyChannel::new(
            format!("{name}.Y").as_str(),
            FlatSamples::F32(data.to_vec()),
        ));
    }
    let layer = Layer::new(
        (width as usize, height as usize),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

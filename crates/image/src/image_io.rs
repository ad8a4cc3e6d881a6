//! Image files. Reading for comparison: fogbank's EXR (colour plus a
//! `variance` layer), EXR from other tools, and 8-bit sRGB PNG. Writing:
//! linear float EXR (colour, a `variance` layer holding the per-pixel
//! variance of the mean, or any named layers) and tone-mapped sRGB PNG.
//!
//! Every error names the file, and no malformed file can panic the caller:
//! decoder panics are caught and turned into errors, because a comparison
//! run over hundreds of renders must report a bad file, not abort.

use crate::tonemap::ToneMapping;
pub use crate::tonemap::{linear_to_srgb, srgb_to_linear};
use std::io::Read;
use std::path::Path;

/// An image ready for comparison.
///
/// `rgb` is always linear (PNG values are decoded from sRGB), so the HDR
/// metrics never see display-encoded values. Pixels are row-major, top row
/// first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    /// Linear RGB per pixel.
    pub rgb: Vec<[f32; 3]>,
    /// Per-pixel variance of the mean (fogbank's `variance.R/G/B`), when the
    /// file has it; the z-test needs it.
    pub variance: Option<Vec<[f32; 3]>>,
    /// True when the values came from an 8-bit (or 16-bit) sRGB PNG: such an
    /// image is display-referred and bounded to [0, 1], so FLIP compares it
    /// with LDR-FLIP instead of HDR-FLIP.
    pub is_srgb8: bool,
}

impl Image {
    /// A linear image without variance.
    pub fn new(width: usize, height: usize, rgb: Vec<[f32; 3]>) -> Image {
        assert_eq!(
            rgb.len(),
            width * height,
            "rgb must hold width·height pixels"
        );
        Image {
            width,
            height,
            rgb,
            variance: None,
            is_srgb8: false,
        }
    }

    /// A constant-colour image, mostly for tests.
    pub fn filled(width: usize, height: usize, c: [f32; 3]) -> Image {
        Image::new(width, height, vec![c; width * height])
    }

    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.width * self.height
    }

    /// True for a 0×0 (or 0×n) image.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Reads an EXR or PNG, recognised by its magic bytes (not its extension, so
/// a misnamed file still reads or fails with a clear message).
pub fn read_image(path: impl AsRef<Path>) -> Result<Image, String> {
    let path = path.as_ref();
    let name = path.display();
    let mut magic = [0u8; 8];
    let n = std::fs::File::open(path)
        .and_then(|mut f| {
            let mut n = 0;
            while n < magic.len() {
                let k = f.read(&mut magic[n..])?;
                if k == 0 {
                    break;
                }
                n += k;
            }
            Ok(n)
        })
        .map_err(|e| format!("{name}: {e}"))?;
    let result = if n >= 4 && magic[..4] == [0x76, 0x2f, 0x31, 0x01] {
        guarded(|| read_exr(path))
    } else if n >= 8 && magic == [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a] {
        guarded(|| read_png(path))
    } else {
        Err("not an EXR or PNG file".to_string())
    };
    result.map_err(|e| format!("{name}: {e}"))
}

/// Runs a decoder, turning a panic inside it into an error: the decoders
/// are third-party code fed with untrusted bytes.
fn guarded(f: impl FnOnce() -> Result<Image, String>) -> Result<Image, String> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f))
        .unwrap_or_else(|_| Err("the decoder failed on malformed data".to_string()))
}

fn read_png(path: &Path) -> Result<Image, String> {
    let reader = image::ImageReader::open(path)
        .map_err(|e| e.to_string())?
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    let img = reader.decode().map_err(|e| e.to_string())?;
    let (width, height) = (img.width() as usize, img.height() as usize);
    // 16-bit PNGs keep their precision; alpha is ignored (renders are opaque).
    let rgb: Vec<[f32; 3]> =
        if img.color().bits_per_pixel() / img.color().channel_count() as u16 > 8 {
            img.to_rgb32f()
                .pixels()
                .map(|p| p.0.map(srgb_to_linear))
                .collect()
        } else {
            let lut: Vec<f32> = (0..256).map(|b| srgb_to_linear(b as f32 / 255.0)).collect();
            img.to_rgb8()
                .pixels()
                .map(|p| p.0.map(|b| lut[b as usize]))
                .collect()
        };
    Ok(Image {
        width,
        height,
        rgb,
        variance: None,
        is_srgb8: true,
    })
}

/// The names of an EXR layer's channels, in the file's (sorted) order.
pub fn channel_names<S>(layer: &exr::prelude::Layer<exr::prelude::AnyChannels<S>>) -> Vec<String> {
    layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect()
}

fn read_exr(path: &Path) -> Result<Image, String> {
    use exr::prelude::{read, ReadChannels, ReadLayers};
    // Pedantic: a truncated or corrupt file must be an error, not an image
    // with silently zeroed blocks.
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .pedantic()
        .from_file(path)
        .map_err(|e| e.to_string())?;

    // The first layer (part) holding colour; single-layer files are the norm.
    let mut seen: Vec<String> = Vec::new();
    for layer in &image.layer_data {
        let names = channel_names(layer);
        let (width, height) = (layer.size.x(), layer.size.y());
        let find = |n: &str| names.iter().position(|x| x == n);
        let plane = |i: usize| -> Result<Vec<f32>, String> {
            let s = &layer.channel_data.list[i].sample_data;
            if s.len() != width * height {
                return Err(format!(
                    "channel {} has {} samples for a {width}×{height} image (subsampled channels are not supported)",
                    names[i],
                    s.len()
                ));
            }
            Ok(s.values_as_f32().collect())
        };
        let colour = match (find("R"), find("G"), find("B"), find("Y")) {
            (Some(r), Some(g), Some(b), _) => Some([plane(r)?, plane(g)?, plane(b)?]),
            (None, None, None, Some(y)) => {
                let y = plane(y)?;
                Some([y.clone(), y.clone(), y])
            }
            _ => None,
        };
        let Some([r, g, b]) = colour else {
            seen.extend(names);
            continue;
        };
        let rgb = (0..width * height).map(|i| [r[i], g[i], b[i]]).collect();
        let vnames = ["variance.R", "variance.G", "variance.B"];
        let vidx: Vec<Option<usize>> = vnames.iter().map(|n| find(n)).collect();
        let variance = match (vidx[0], vidx[1], vidx[2]) {
            (Some(vr), Some(vg), Some(vb)) => {
                let (vr, vg, vb) = (plane(vr)?, plane(vg)?, plane(vb)?);
                Some((0..width * height).map(|i| [vr[i], vg[i], vb[i]]).collect())
            }
            (None, None, None) => None,
            _ => {
                let missing: Vec<&str> = vnames
                    .iter()
                    .zip(&vidx)
                    .filter(|(_, i)| i.is_none())
                    .map(|(n, _)| *n)
                    .collect();
                return Err(format!(
                    "incomplete variance layer: missing {}",
                    missing.join(", ")
                ));
            }
        };
        return Ok(Image {
            width,
            height,
            rgb,
            variance,
            is_srgb8: false,
        });
    }
    Err(format!(
        "no R, G, B (or Y) channels; found [{}]",
        seen.join(", ")
    ))
}

/// Reads a reference and a test image and checks that they can be compared
/// (same resolution); errors name the offending file.
pub fn read_pair(
    reference: impl AsRef<Path>,
    test: impl AsRef<Path>,
) -> Result<(Image, Image), String> {
    let (rp, tp) = (reference.as_ref(), test.as_ref());
    let r = read_image(rp)?;
    let t = read_image(tp)?;
    if (r.width, r.height) != (t.width, t.height) {
        return Err(format!(
            "size mismatch: {} is {}×{} but {} is {}×{}",
            rp.display(),
            r.width,
            r.height,
            tp.display(),
            t.width,
            t.height
        ));
    }
    if r.is_empty() {
        return Err(format!("{}: the image has no pixels", rp.display()));
    }
    Ok((r, t))
}

/// Writes R, G, B and, if given, `variance.R/G/B` as 32-bit float channels
/// of one part; OpenEXR tools and tev read the `variance.` prefix as a layer.
pub fn write_exr(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[[f32; 3]],
    variance: Option<&[[f32; 3]]>,
) -> Result<(), String> {
    let mut layers = vec![("", rgb.to_vec())];
    if let Some(v) = variance {
        layers.push(("variance", v.to_vec()));
    }
    write_exr_channels(path, width, height, &layers, None)
}

/// Writes an 8-bit sRGB PNG of the linear values through `tone` (exposure
/// and curve; `ToneMapping::default()` is the plain clamped sRGB encoding).
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[[f32; 3]],
    tone: &ToneMapping,
) -> Result<(), String> {
    let bytes: Vec<u8> = rgb.iter().flat_map(|&p| tone.display8(p)).collect();
    image::save_buffer(path, &bytes, width, height, image::ColorType::Rgb8)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The PNG file [`write_png`] writes, in memory (a notebook shows it).
pub fn encode_png(
    width: u32,
    height: u32,
    rgb: &[[f32; 3]],
    tone: &ToneMapping,
) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let bytes: Vec<u8> = rgb.iter().flat_map(|&p| tone.display8(p)).collect();
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(&bytes, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| format!("PNG: {e}"))?;
    Ok(out)
}

/// Writes named RGB layers (`NAME.R/G/B`; plain `R/G/B` for an empty name)
/// and an optional scalar channel (`NAME.Y`) into one EXR part.
pub fn write_exr_channels(
    path: &Path,
    width: u32,
    height: u32,
    layers: &[(&str, Vec<[f32; 3]>)],
    scalar: Option<(&str, &[f32])>,
) -> Result<(), String> {
    use exr::prelude::{
        AnyChannel, AnyChannels, Encoding, FlatSamples, Layer, LayerAttributes, WritableImage,
    };
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
    exr::prelude::Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

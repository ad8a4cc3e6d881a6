//! Mitsuba 3's `bitmap` texture: an image file looked up at a surface's
//! texture coordinates, bilinearly (the default) or nearest, with the
//! `repeat`, `mirror` or `clamp` wrap mode.
//!
//! Parameters (TOML `{ type = "bitmap", … }`, XML `<texture type="bitmap">`):
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `filename` | — | PNG, JPEG, OpenEXR or Radiance HDR, relative to the scene file |
//! | `filter_type` | `bilinear` | `bilinear` or `nearest` |
//! | `wrap_mode` | `repeat` | `repeat`, `mirror` or `clamp` |
//! | `raw` | `false` | keep 8/16-bit values as stored instead of decoding sRGB |
//! | `to_uv` | identity | affine map applied to the texture coordinates first |
//!
//! Conventions are Mitsuba's (`src/textures/bitmap.cpp`, Dr.Jit's
//! `tex_eval`): texel rows in file order, so v = 0 is the file's top row;
//! 8- and 16-bit files are sRGB-encoded unless `raw`, decoded to linear and
//! stored in half precision (Mitsuba's `format = "auto"`), float files are
//! linear and kept in single precision; grey (Y, YA) files keep one channel,
//! alpha is dropped; a dimension of one texel is doubled (Mitsuba resamples
//! images under 2×2 with a tent filter, which repeats a lone row or column).

use crate::error::SceneError;
use glam::{Affine2, Vec2, Vec3};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Interpolation of the texels (`filter_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BitmapFilter {
    Bilinear,
    Nearest,
}

/// Lookups outside [0, 1)² (`wrap_mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    Repeat,
    Mirror,
    Clamp,
}

impl BitmapFilter {
    /// Every filter's name, in the order of its id on the GPU (`FILTER_*`).
    pub const NAMES: [&'static str; 2] = ["bilinear", "nearest"];

    pub fn id(self) -> u32 {
        self as u32
    }

    pub fn parse(s: &str, key: &str) -> Result<BitmapFilter, SceneError> {
        match s {
            "bilinear" => Ok(BitmapFilter::Bilinear),
            "nearest" => Ok(BitmapFilter::Nearest),
            _ => Err(SceneError(format!(
                "{key}: filter_type {s:?}: expected \"bilinear\" or \"nearest\""
            ))),
        }
    }
}

impl WrapMode {
    /// Every mode's name, in the order of its id on the GPU (`WRAP_*`).
    pub const NAMES: [&'static str; 3] = ["repeat", "mirror", "clamp"];

    pub fn id(self) -> u32 {
        self as u32
    }

    pub fn parse(s: &str, key: &str) -> Result<WrapMode, SceneError> {
        match s {
            "repeat" => Ok(WrapMode::Repeat),
            "mirror" => Ok(WrapMode::Mirror),
            "clamp" => Ok(WrapMode::Clamp),
            _ => Err(SceneError(format!(
                "{key}: wrap_mode {s:?}: expected \"repeat\", \"mirror\" or \"clamp\""
            ))),
        }
    }

    /// The texel index of integer coordinate `i` along a side of `n` texels
    /// (Dr.Jit's `tex_wrap`: a Euclidean modulo; mirror reflects every
    /// other period).
    pub fn wrap(self, i: i32, n: i32) -> i32 {
        match self {
            WrapMode::Clamp => i.clamp(0, n - 1),
            WrapMode::Repeat => i.rem_euclid(n),
            WrapMode::Mirror => {
                let m = i.rem_euclid(n);
                if i.div_euclid(n) % 2 == 0 {
                    m
                } else {
                    n - 1 - m
                }
            }
        }
    }
}

/// Images larger than this many texels (8192², 768 MiB as f32 RGB) are
/// refused before decoding.
pub const MAX_TEXELS: u64 = 1 << 26;

/// A loaded bitmap texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Bitmap {
    pub width: u32,
    pub height: u32,
    /// 1 (grey) or 3 (RGB).
    pub channels: u32,
    /// Row-major texels, `channels` values each, linear; shared by every
    /// texture that reads the same file ([`BitmapFiles`]).
    pub texels: Arc<[f32]>,
    pub filter: BitmapFilter,
    pub wrap: WrapMode,
    pub to_uv: Affine2,
}

impl Bitmap {
    /// Texel (x, y) as RGB (a grey texel on every channel).
    fn texel(&self, x: i32, y: i32) -> Vec3 {
        let x = self.wrap.wrap(x, self.width as i32) as usize;
        let y = self.wrap.wrap(y, self.height as i32) as usize;
        let i = (y * self.width as usize + x) * self.channels as usize;
        if self.channels == 1 {
            Vec3::splat(self.texels[i])
        } else {
            Vec3::new(self.texels[i], self.texels[i + 1], self.texels[i + 2])
        }
    }

    /// The texture at surface coordinates `uv` (Dr.Jit's `tex_eval`: texel
    /// centres at half-integers for bilinear lookups). Texel coordinates
    /// are clamped to ±2²⁴, where f32 no longer tells texels apart, so that
    /// integer arithmetic cannot overflow (`bitmap.wgsl` likewise).
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        let uv = self.to_uv.transform_point2(uv);
        let res = Vec2::new(self.width as f32, self.height as f32);
        let limit = Vec2::splat(16_777_216.0);
        match self.filter {
            BitmapFilter::Nearest => {
                let p = (uv * res).clamp(-limit, limit).floor();
                self.texel(p.x as i32, p.y as i32)
            }
            BitmapFilter::Bilinear => {
                let p = (uv * res - 0.5).clamp(-limit, limit);
                let i = p.floor();
                let w1 = p - i;
                let w0 = Vec2::ONE - w1;
                let (x, y) = (i.x as i32, i.y as i32);
                self.texel(x, y) * (w0.x * w0.y)
                    + self.texel(x + 1, y) * (w1.x * w0.y)
                    + self.texel(x, y + 1) * (w0.x * w1.y)
                    + self.texel(x + 1, y + 1) * (w1.x * w1.y)
            }
        }
    }

    /// The mean texel (RGB).
    pub fn mean(&self) -> Vec3 {
        let n = (self.width * self.height) as f64;
        let mut s = [0.0f64; 3];
        for t in self.texels.chunks(self.channels as usize) {
            for (c, sum) in s.iter_mut().enumerate() {
                *sum += t[c.min(t.len() - 1)] as f64;
            }
        }
        Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
    }

    /// Loads `path` (see the module's table for formats and conventions).
    pub fn load(
        path: &Path,
        raw: bool,
        filter: BitmapFilter,
        wrap: WrapMode,
        to_uv: Affine2,
    ) -> Result<Bitmap, SceneError> {
        let name = path.display();
        let (width, height, channels, mut texels) =
            decode(path, raw).map_err(|e| SceneError(format!("{name}: {e}")))?;
        if width == 0 || height == 0 {
            return Err(SceneError(format!("{name}: the image is empty")));
        }
        let (mut width, mut height) = (width, height);
        let c = channels as usize;
        if width == 1 {
            texels = texels.chunks(c).flat_map(|t| [t, t].concat()).collect();
            width = 2;
        }
        if height == 1 {
            texels = [texels.clone(), texels].concat();
            height = 2;
        }
        Ok(Bitmap {
            width,
            height,
            channels,
            texels: texels.into(),
            filter,
            wrap,
            to_uv,
        })
    }
}

/// The bitmap files of one scene, each decoded once: textures that read the
/// same file (with the same `raw`) share its texels, in memory and in the
/// GPU's surface buffer, whatever their filter, wrap and `to_uv`.
#[derive(Debug)]
pub struct BitmapFiles {
    base: PathBuf,
    decoded: RefCell<HashMap<(PathBuf, bool), Bitmap>>,
}

impl BitmapFiles {
    /// Files relative to `base` (the scene file's folder).
    pub fn new(base: &Path) -> BitmapFiles {
        BitmapFiles {
            base: base.to_path_buf(),
            decoded: RefCell::new(HashMap::new()),
        }
    }

    /// [`Bitmap::load`] of `filename`, decoding it on its first use only.
    pub fn load(
        &self,
        filename: &str,
        raw: bool,
        filter: BitmapFilter,
        wrap: WrapMode,
        to_uv: Affine2,
    ) -> Result<Bitmap, SceneError> {
        let path = self.base.join(filename);
        let key = (path.clone(), raw);
        if let Some(b) = self.decoded.borrow().get(&key) {
            return Ok(Bitmap {
                filter,
                wrap,
                to_uv,
                ..b.clone()
            });
        }
        let b = Bitmap::load(&path, raw, filter, wrap, to_uv)?;
        self.decoded.borrow_mut().insert(key, b.clone());
        Ok(b)
    }
}

/// sRGB's decoding curve (IEC 61966-2-1).
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

type Decoded = (u32, u32, u32, Vec<f32>);

fn decode(path: &Path, raw: bool) -> Result<Decoded, String> {
    let is_exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if is_exr {
        let image = fogbank_image::image_io::read_image(path)?;
        let texels = image.rgb.iter().flatten().copied().collect();
        return Ok((image.width as u32, image.height as u32, 3, texels));
    }
    use image::ImageDecoder;
    let decoder = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| e.to_string())?
        .into_decoder()
        .map_err(|e| format!("not a PNG, JPEG, EXR or HDR image: {e}"))?;
    let (w, h) = decoder.dimensions();
    if w as u64 * h as u64 > MAX_TEXELS {
        return Err(format!("{w}×{h} texels exceed the limit of {MAX_TEXELS}"));
    }
    let image = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        image::DynamicImage::from_decoder(decoder)
    }))
    .map_err(|_| "the decoder failed".to_string())?
    .map_err(|e| e.to_string())?;
    use image::ColorType as C;
    let color = image.color();
    let grey = matches!(color, C::L8 | C::La8 | C::L16 | C::La16);
    let float = matches!(color, C::Rgb32F | C::Rgba32F);
    // Mitsuba's format "auto": half precision for files of ≤ 16 bits.
    let encode = |v: f32| {
        let v = if raw || float { v } else { srgb_to_linear(v) };
        if float {
            v
        } else {
            half::f16::from_f32(v).to_f32()
        }
    };
    let (channels, texels): (u32, Vec<f32>) = if grey {
        let g = image.to_luma32f();
        (1, g.into_raw().into_iter().map(encode).collect())
    } else {
        let rgb = image.into_rgb32f();
        (3, rgb.into_raw().into_iter().map(encode).collect())
    };
    Ok((w, h, channels, texels))
}

#[cfg(test)]
mod bitmap_test {
    use super::*;

    fn grid(filter: BitmapFilter, wrap: WrapMode) -> Bitmap {
        // 3×2 grey texels 0..6, row 0 first.
        Bitmap {
            width: 3,
            height: 2,
            channels: 1,
            texels: (0..6).map(|i| i as f32).collect::<Vec<_>>().into(),
            filter,
            wrap,
            to_uv: Affine2::IDENTITY,
        }
    }

    #[test]
    fn wrap_modes_follow_dr_jit() {
        let r: Vec<i32> = (-5..6).map(|i| WrapMode::Repeat.wrap(i, 4)).collect();
        assert_eq!(r, [3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1]);
        let m: Vec<i32> = (-5..6).map(|i| WrapMode::Mirror.wrap(i, 4)).collect();
        assert_eq!(m, [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2]);
        let c: Vec<i32> = (-2..6).map(|i| WrapMode::Clamp.wrap(i, 4)).collect();
        assert_eq!(c, [0, 0, 0, 1, 2, 3, 3, 3]);
    }

    #[test]
    fn nearest_and_bilinear_lookups() {
        let n = grid(BitmapFilter::Nearest, WrapMode::Repeat);
        // v = 0 is the first row; texel (2, 1) = 5.
        assert_eq!(n.eval(Vec2::new(0.1, 0.1)).x, 0.0);
        assert_eq!(n.eval(Vec2::new(0.9, 0.9)).x, 5.0);
        let b = grid(BitmapFilter::Bilinear, WrapMode::Clamp);
        // At a texel centre the texel itself.
        assert_eq!(b.eval(Vec2::new(0.5 / 3.0, 0.25)).x, 0.0);
        assert!((b.eval(Vec2::new(1.5 / 3.0, 0.75)).x - 4.0).abs() < 1e-5);
        // Halfway between the centres of texels 0, 1, 3, 4.
        let v = b.eval(Vec2::new(1.0 / 3.0, 0.5)).x;
        assert!((v - 2.0).abs() < 1e-5, "{v}");
        // Repeat wraps the left neighbour of column 0 to column 2.
        let r = grid(BitmapFilter::Bilinear, WrapMode::Repeat);
        let v = r.eval(Vec2::new(0.0, 0.25)).x;
        assert!((v - 1.0).abs() < 1e-5, "{v}"); // (0 + 2) / 2
        assert_eq!(r.mean(), Vec3::splat(2.5));
    }

    #[test]
    fn png_is_decoded_from_srgb_unless_raw() {
        let dir = std::env::temp_dir().join(format!("fogbank_bitmap_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.png");
        let img = image::RgbImage::from_fn(1, 3, |_, y| image::Rgb([0, 128, (y * 100) as u8]));
        img.save(&p).unwrap();
        let id = Affine2::IDENTITY;
        let b = Bitmap::load(&p, false, BitmapFilter::Nearest, WrapMode::Repeat, id).unwrap();
        // One column is doubled to two.
        assert_eq!((b.width, b.height, b.channels), (2, 3, 3));
        let g = srgb_to_linear(128.0 / 255.0);
        assert!((b.texels[1] - g).abs() < 1e-3 * g, "{}", b.texels[1]);
        assert_eq!(b.texels[1], half::f16::from_f32(g).to_f32());
        assert_eq!(b.texels[..3], b.texels[3..6]);
        let raw = Bitmap::load(&p, true, BitmapFilter::Nearest, WrapMode::Repeat, id).unwrap();
        assert!((raw.texels[1] - 128.0 / 255.0).abs() < 1e-3);
        // JPEG, grey: one channel.
        let j = dir.join("t.jpg");
        image::GrayImage::from_pixel(4, 4, image::Luma([200]))
            .save(&j)
            .unwrap();
        let b = Bitmap::load(&j, true, BitmapFilter::Bilinear, WrapMode::Clamp, id).unwrap();
        assert_eq!((b.width, b.height, b.channels), (4, 4, 1));
        assert!((b.eval(Vec2::splat(0.5)).x - 200.0 / 255.0).abs() < 0.01);
        // Bad files are refused with their name.
        std::fs::write(dir.join("bad.png"), b"not an image").unwrap();
        let e = Bitmap::load(
            &dir.join("bad.png"),
            false,
            BitmapFilter::Nearest,
            WrapMode::Repeat,
            id,
        )
        .unwrap_err();
        assert!(e.0.contains("bad.png"), "{e:?}");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A scene's textures that read one file share its texels, each with
    /// its own lookup parameters; `raw` and other files decode apart.
    #[test]
    fn files_are_decoded_once_per_scene() {
        let dir = std::env::temp_dir().join(format!("fogbank_bitmaps_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]))
            .save(dir.join("a.png"))
            .unwrap();
        image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]))
            .save(dir.join("b.png"))
            .unwrap();
        let files = BitmapFiles::new(&dir);
        let id = Affine2::IDENTITY;
        let a = files
            .load("a.png", false, BitmapFilter::Nearest, WrapMode::Repeat, id)
            .unwrap();
        let shifted = Affine2::from_translation(Vec2::new(0.5, 0.0));
        let again = files
            .load(
                "a.png",
                false,
                BitmapFilter::Bilinear,
                WrapMode::Clamp,
                shifted,
            )
            .unwrap();
        assert!(Arc::ptr_eq(&a.texels, &again.texels));
        assert_eq!(
            (again.filter, again.wrap, again.to_uv),
            (BitmapFilter::Bilinear, WrapMode::Clamp, shifted)
        );
        let raw = files
            .load("a.png", true, BitmapFilter::Nearest, WrapMode::Repeat, id)
            .unwrap();
        let other = files
            .load("b.png", false, BitmapFilter::Nearest, WrapMode::Repeat, id)
            .unwrap();
        assert!(!Arc::ptr_eq(&a.texels, &raw.texels) && a.texels != raw.texels);
        assert!(!Arc::ptr_eq(&a.texels, &other.texels) && a.texels == other.texels);
        std::fs::remove_dir_all(&dir).ok();
    }
}

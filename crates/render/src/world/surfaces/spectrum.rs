//! A reflectance parameter of a `bsdf` table: a grey number, an RGB triple
//! or a texture table (`checkerboard`, `bitmap`), built into a [`Texture`]
//! with file names relative to the scene's folder.

use crate::error::SceneError;
use crate::world::bitmap::{BitmapFiles, BitmapFilter, WrapMode};
use crate::world::texture::Texture;
use glam::{Affine2, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A reflectance: grey, RGB, or a texture.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum SpectrumDesc {
    Grey(f32),
    Rgb([f32; 3]),
    Texture(TextureDesc),
}

/// Mitsuba's 2-D `to_uv` transform: scale, then translate.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct UvTransformDesc {
    pub scale: Option<[f32; 2]>,
    pub translate: Option<[f32; 2]>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum TextureDesc {
    /// Mitsuba's `checkerboard` (defaults 0.4 and 0.2).
    Checkerboard {
        #[serde(default = "checker0")]
        color0: [f32; 3],
        #[serde(default = "checker1")]
        color1: [f32; 3],
        #[serde(default)]
        to_uv: UvTransformDesc,
    },
    /// Mitsuba's `bitmap` (`world::bitmap`).
    Bitmap {
        filename: String,
        #[serde(default = "bilinear")]
        filter_type: String,
        #[serde(default = "repeat")]
        wrap_mode: String,
        #[serde(default)]
        raw: bool,
        #[serde(default)]
        to_uv: UvTransformDesc,
    },
}

fn bilinear() -> String {
    "bilinear".into()
}
fn repeat() -> String {
    "repeat".into()
}

impl UvTransformDesc {
    fn affine(&self) -> Affine2 {
        Affine2::from_translation(Vec2::from(self.translate.unwrap_or([0.0; 2])))
            * Affine2::from_scale(Vec2::from(self.scale.unwrap_or([1.0; 2])))
    }
}

fn checker0() -> [f32; 3] {
    [0.4; 3]
}
fn checker1() -> [f32; 3] {
    [0.2; 3]
}

impl SpectrumDesc {
    /// The texture; `files` resolves and decodes file names.
    pub(crate) fn texture(&self, key: &str, files: &BitmapFiles) -> Result<Texture, SceneError> {
        let check = |c: [f32; 3]| {
            if c.iter().all(|v| v.is_finite() && *v >= 0.0) {
                Ok(Vec3::from(c))
            } else {
                Err(SceneError(format!(
                    "{key}: {c:?} has a negative or non-finite channel"
                )))
            }
        };
        Ok(match self {
            SpectrumDesc::Grey(v) => Texture::Constant(check([*v; 3])?),
            SpectrumDesc::Rgb(c) => Texture::Constant(check(*c)?),
            SpectrumDesc::Texture(TextureDesc::Checkerboard {
                color0,
                color1,
                to_uv,
            }) => Texture::Checkerboard {
                color0: check(*color0)?,
                color1: check(*color1)?,
                to_uv: to_uv.affine(),
            },
            SpectrumDesc::Texture(TextureDesc::Bitmap {
                filename,
                filter_type,
                wrap_mode,
                raw,
                to_uv,
            }) => Texture::Bitmap(Arc::new(files.load(
                filename,
                *raw,
                BitmapFilter::parse(filter_type, key)?,
                WrapMode::parse(wrap_mode, key)?,
                to_uv.affine(),
            )?)),
        })
    }
}

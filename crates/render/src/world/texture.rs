//! Textures of surface parameters, as Mitsuba 3's: constants, the
//! `checkerboard` and the `bitmap` (`world::bitmap`). `to_uv` maps the
//! surface's texture coordinates first (Mitsuba's `to_uv`, an affine map of
//! the plane).

use super::bitmap::Bitmap;
use glam::{Affine2, Vec2, Vec3};
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    Constant(Vec3),
    /// Mitsuba's defaults: `color0` 0.4, `color1` 0.2, identity `to_uv`.
    Checkerboard {
        color0: Vec3,
        color1: Vec3,
        to_uv: Affine2,
    },
    /// An image file (shared: one load however many shapes use it).
    Bitmap(Arc<Bitmap>),
}

impl Texture {
    /// Every kind's name, in the order of its id on the GPU (`TEXTURE_*`).
    pub const NAMES: [&'static str; 3] = ["constant", "checkerboard", "bitmap"];

    pub fn name(&self) -> &'static str {
        match self {
            Texture::Constant(_) => "constant",
            Texture::Checkerboard { .. } => "checkerboard",
            Texture::Bitmap(_) => "bitmap",
        }
    }

    pub fn eval(&self, uv: Vec2) -> Vec3 {
        match *self {
            Texture::Constant(c) => c,
            Texture::Bitmap(ref b) => b.eval(uv),
            Texture::Checkerboard {
                color0,
                color1,
                to_uv,
            } => {
                let uv = to_uv.transform_point2(uv);
                let f = uv - uv.floor();
                // Mitsuba 3's RGB `eval`: color0 where both coordinates are
                // in the same half of their period. (Its `eval_1`, used for
                // scalar parameters such as roughness, takes the opposite
                // squares — a slip we do not copy.)
                if (f.x > 0.5) == (f.y > 0.5) {
                    color0
                } else {
                    color1
                }
            }
        }
    }

    /// The texture's mean over [0, 1)² (Mitsuba's `mean`, used for sampling
    /// weights such as the plastic's; a bitmap's is its mean texel).
    pub fn mean(&self) -> Vec3 {
        match *self {
            Texture::Constant(c) => c,
            Texture::Bitmap(ref b) => b.mean(),
            Texture::Checkerboard { color0, color1, .. } => 0.5 * (color0 + color1),
        }
    }
}

#[cfg(test)]
mod texture_test {
    use super::*;

    #[test]
    fn checkerboard_squares_and_to_uv() {
        let t = Texture::Checkerboard {
            color0: Vec3::ONE,
            color1: Vec3::ZERO,
            to_uv: Affine2::IDENTITY,
        };
        assert_eq!(t.eval(Vec2::new(0.25, 0.25)), Vec3::ONE);
        assert_eq!(t.eval(Vec2::new(0.75, 0.75)), Vec3::ONE);
        assert_eq!(t.eval(Vec2::new(0.75, 0.25)), Vec3::ZERO);
        // Periodic, also for negative coordinates.
        assert_eq!(
            t.eval(Vec2::new(-0.25, 1.25)),
            t.eval(Vec2::new(0.75, 0.25))
        );
        // to_uv scaling by 2 halves the squares.
        let s = Texture::Checkerboard {
            color0: Vec3::ONE,
            color1: Vec3::ZERO,
            to_uv: Affine2::from_scale(Vec2::splat(2.0)),
        };
        assert_eq!(s.eval(Vec2::new(0.3, 0.1)), Vec3::ZERO);
        assert_eq!(t.mean(), Vec3::splat(0.5));
    }
}

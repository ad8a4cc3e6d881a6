//! A volumetric path as a reservoir stores it (seed 002 §3.2, §4.2): the
//! camera vertex x_0 is the pixel's own, so a path is its distances and
//! directions, which direction reuse copies onto another pixel's primary
//! ray (§4.2, Fig. 6): z_1 along the new primary ray, then ω_i and z_i.
//! Its end is the environment seen through the medium (Eq. 1, second term),
//! a light reached by next-event estimation from x_k, or the medium's own
//! emission at x_k. A last vertex in emissive medium (k ≥ 2) is kept fixed
//! in space, as the paper does for emitters; its measure is then volume,
//! so p̂ and F carry 1/|x_k − x_{k−1}|² on the final segment.

use fogbank_math::Vec3;

/// Longest path a reservoir stores, in medium vertices (the paper uses up
/// to 7).
pub const MAX_K: usize = 8;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathEnd {
    /// k = 0: the environment along the primary ray.
    Background,
    /// Next-event estimation from x_k to light `light`.
    Light,
    /// Emission σ_a L_e at x_k.
    Emission,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSample {
    pub end: PathEnd,
    /// Medium vertices x_1 … x_k.
    pub k: u8,
    /// Index of the light of a `Light` end.
    pub light: u16,
    /// z[i] = distance from x_i to x_{i+1} (z_{i+1} of the paper).
    pub z: [f32; MAX_K],
    /// dir[i] = ω_{i+1}, the direction leaving x_{i+1} (i + 1 < k).
    pub dir: [Vec3; MAX_K],
    /// A `Light` end: the direction to an environment or directional light
    /// (kept, §4.2); positional lights keep their position instead.
    pub light_dir: Vec3,
    /// An `Emission` end with k ≥ 2: the emitting vertex x_k, kept fixed.
    pub emitter: Vec3,
}

impl PathSample {
    pub const BACKGROUND: PathSample = PathSample {
        end: PathEnd::Background,
        k: 0,
        light: 0,
        z: [0.0; MAX_K],
        dir: [Vec3::ZERO; MAX_K],
        light_dir: Vec3::ZERO,
        emitter: Vec3::ZERO,
    };

    /// Whether the last vertex is a fixed point in space (volume measure).
    #[inline]
    pub fn fixed_emitter(&self) -> bool {
        self.end == PathEnd::Emission && self.k >= 2
    }
}

//! A volumetric path as a reservoir stores it (Lin et al. 2021 §3.2, §4.2): the
//! camera vertex x_0 is the pixel's own, so a path is its distances and
//! directions, which direction reuse copies onto another pixel's primary
//! ray (§4.2, Fig. 6): z_1 along the new primary ray, then ω_i and z_i.
//! Its end is the environment seen through the medium (Eq. 1, second term),
//! a light reached by next-event estimation from x_k, or the medium's own
//! emission at x_k. A last vertex in emissive medium (k ≥ 2) is kept fixed
//! in space, as the paper does for emitters; vertex reuse (the option of
//! §4.2) keeps every vertex from x_2 on fixed. A fixed vertex's measure is
//! volume, so p̂ and F carry 1/|x_i − x_{i−1}|² on the segment reaching it.
//!
//! Surfaces (Lin et al. 2021 §4.2): a vertex may lie on a surface — the
//! closest one along (x_{i−1}, ω_{i−1}), wherever reuse moves that ray, so
//! it has no distance of its own and its factor in F is T·f_s·|cos θ|
//! instead of T·σ_s·ρ. A `Light` end on an emitting shape keeps its point
//! on the light (`light_point`), in that point's area measure: the last
//! segment carries L_e·|cos θ_q|/|q − x_k|².

use fogbank_math::Vec3;

/// Longest path a reservoir stores, in vertices (the paper uses up to 7;
/// at most 8: `surface` is one byte).
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
    /// Vertices x_1 … x_k.
    pub k: u8,
    /// Bit i set: x_{i+1} lies on a surface.
    pub surface: u8,
    /// Index of the light of a `Light` end.
    pub light: u16,
    /// z[i] = distance from x_i to x_{i+1} (z_{i+1} of the paper).
    pub z: [f32; MAX_K],
    /// dir[i] = ω_{i+1}, the direction leaving x_{i+1} (i + 1 < k).
    pub dir: [Vec3; MAX_K],
    /// A `Light` end: the direction to an environment or directional light
    /// (kept, §4.2); positional lights keep their position instead.
    pub light_dir: Vec3,
    /// A `Light` end on an emitting shape: its point on the light.
    pub light_point: Vec3,
    /// x[i] = x_{i+1}, the vertices where the path was found; those from
    /// index `fixed_from` on (never x_1) stay there under reuse.
    pub x: [Vec3; MAX_K],
    /// First vertex index kept fixed in space ([`NONE_FIXED`]: none).
    pub fixed_from: u8,
}

/// `fixed_from` of a path whose vertices all follow its directions.
pub const NONE_FIXED: u8 = u8::MAX;

impl PathSample {
    pub const BACKGROUND: PathSample = PathSample {
        end: PathEnd::Background,
        k: 0,
        surface: 0,
        light: 0,
        z: [0.0; MAX_K],
        dir: [Vec3::ZERO; MAX_K],
        light_dir: Vec3::ZERO,
        light_point: Vec3::ZERO,
        x: [Vec3::ZERO; MAX_K],
        fixed_from: NONE_FIXED,
    };

    /// Whether vertex index `i` (x_{i+1}) lies on a surface.
    #[inline]
    pub fn on_surface(&self, i: usize) -> bool {
        self.surface & (1 << i) != 0
    }

    /// Whether vertex index `i` (x_{i+1}) is a fixed point in space.
    #[inline]
    pub fn is_fixed(&self, i: usize) -> bool {
        i >= 1 && i >= self.fixed_from as usize
    }
}

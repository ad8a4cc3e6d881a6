//! What a BSDF's `sample` returns, and the small sampling helpers the
//! lobes share.

use glam::Vec3;

/// A sampled direction with its BSDF value and pdf (for a delta lobe: the
/// lobe's discrete probability, and `f` the value that makes
/// f·|cos θi|/pdf the path weight).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    pub wi: Vec3,
    pub f: Vec3,
    pub pdf: f32,
    pub delta: bool,
}

impl BsdfSample {
    /// The path throughput factor f·|cos θi|/pdf.
    pub fn weight(&self) -> Vec3 {
        self.f * self.wi.z.abs() / self.pdf
    }
}

pub(super) fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}

/// Cosine-weighted direction in the upper hemisphere (Malley's method with
/// a concentric disk map, pbrt-v4 §A.5.3).
pub fn sample_cosine(u: [f32; 2]) -> Vec3 {
    let (x, y) = fogbank_math::warp::concentric_disk(u);
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

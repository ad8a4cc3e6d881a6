//! What a BSDF's `sample` returns, and the small sampling helpers the
//! lobes share.

use glam::Vec3;
use std::f32::consts::PI;

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
    let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    let (x, y) = if a == 0.0 && b == 0.0 {
        (0.0, 0.0)
    } else if a.abs() > b.abs() {
        let phi = PI / 4.0 * (b / a);
        (a * phi.cos(), a * phi.sin())
    } else {
        let phi = PI / 2.0 - PI / 4.0 * (a / b);
        (b * phi.cos(), b * phi.sin())
    };
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

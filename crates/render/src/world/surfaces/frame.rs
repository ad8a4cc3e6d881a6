//! The local shading frame BSDFs work in: z along the shading normal.

use fogbank_math::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct ShadingFrame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl ShadingFrame {
    /// A right-handed frame around unit `n`.
    pub fn new(n: Vec3) -> ShadingFrame {
        let (s, t) = n.any_orthonormal_pair();
        ShadingFrame { s, t, n }
    }

    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

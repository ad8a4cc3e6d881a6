//! Integrators: one file each. An integrator maps a pixel sample (a key for
//! its random streams) to radiance and the lookups it cost.

pub mod transmittance;

use crate::scene::{IntegratorKind, Scene};
use fogbank_math::{SampleKey, Vec3};

/// Random-stream dimensions, so each purpose has its own PCG32 stream.
pub mod dim {
    pub const CAMERA: u32 = 0;
    pub const ESTIMATOR: u32 = 1;
}

#[derive(Clone, Copy, Debug, Default)]
pub struct PixelSample {
    pub radiance: Vec3,
    pub lookups: u32,
}

/// One sample of pixel `(x, y)` with sample index `key.sample`.
pub fn sample_pixel(scene: &Scene, x: u32, y: u32, key: SampleKey) -> PixelSample {
    match &scene.integrator {
        IntegratorKind::Transmittance {
            estimator,
            background,
        } => transmittance::sample(scene, *estimator, *background, x, y, key),
    }
}

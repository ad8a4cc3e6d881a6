//! Integrators: one file each. An integrator maps a pixel sample (a key for
//! its random streams) to radiance and the lookups it cost.

pub mod direct;
pub mod media;
pub mod next_event;
pub mod point_mis;
pub mod transmittance;
pub mod volpath;

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

/// The primary ray of a pixel sample: jittered within the pixel, or through
/// its centre when `render.pixel_jitter` is off.
pub fn primary_ray(scene: &Scene, x: u32, y: u32, key: SampleKey) -> fogbank_math::Ray {
    let (jx, jy) = if scene.desc.render.pixel_jitter {
        let mut cam = SampleKey {
            dimension: dim::CAMERA,
            ..key
        }
        .rng();
        (cam.next_f32(), cam.next_f32())
    } else {
        (0.5, 0.5)
    };
    scene.camera.ray(x as f32 + jx, y as f32 + jy)
}

/// One sample of pixel `(x, y)` with sample index `key.sample`.
pub fn sample_pixel(scene: &Scene, x: u32, y: u32, key: SampleKey) -> PixelSample {
    match &scene.integrator {
        IntegratorKind::Transmittance {
            estimator,
            background,
        } => transmittance::sample(scene, *estimator, *background, x, y, key),
        IntegratorKind::Direct(d) => d.sample(scene, x, y, key),
        IntegratorKind::VolPath(v) => v.sample(scene, x, y, key),
        IntegratorKind::PointMis(p) => p.sample(scene, x, y, key),
    }
}

//! Pinhole camera. Pixel (0, 0) is the top-left corner; a sample at
//! continuous film position (x, y) maps through the tangent plane.

use fogbank_math::{Ray, Vec3};

#[derive(Clone, Debug)]
pub struct Camera {
    pub origin: Vec3,
    pub width: u32,
    pub height: u32,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// Half-extent of the image plane at distance 1, per axis.
    tan_half: [f32; 2],
}

impl Camera {
    pub fn new(
        from: Vec3,
        to: Vec3,
        up: Vec3,
        fov_deg: f32,
        fov_axis_x: bool,
        width: u32,
        height: u32,
    ) -> Option<Self> {
        let forward = (to - from).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        let up = right.cross(forward);
        let t = (0.5 * fov_deg.to_radians()).tan();
        let aspect = width as f32 / height as f32;
        let tan_half = if fov_axis_x {
            [t, t / aspect]
        } else {
            [t * aspect, t]
        };
        Some(Camera {
            origin: from,
            width,
            height,
            forward,
            right,
            up,
            tan_half,
        })
    }

    /// (origin, forward, right, up, tan_half): what a GPU kernel needs to
    /// reproduce [`Camera::ray`].
    pub fn basis(&self) -> (Vec3, Vec3, Vec3, Vec3, [f32; 2]) {
        (
            self.origin,
            self.forward,
            self.right,
            self.up,
            self.tan_half,
        )
    }

    /// Primary ray through film position `(x, y)` in pixels; unit direction,
    /// so ray parameters are world distances.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let sx = (2.0 * x / self.width as f32 - 1.0) * self.tan_half[0];
        let sy = (1.0 - 2.0 * y / self.height as f32) * self.tan_half[1];
        Ray::new(
            self.origin,
            (self.forward + sx * self.right + sy * self.up).normalize(),
        )
    }
}

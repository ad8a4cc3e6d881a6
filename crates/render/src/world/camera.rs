//! Pinhole camera. Pixel (0, 0) is the top-left corner; a sample at
//! continuous film position (x, y) maps through the tangent plane. Clip
//! planes as Mitsuba's perspective sensor has them: a ray starts on the near
//! plane (at distance `near / cos θ` along its direction, θ from the view
//! axis) and its first segment ends on the far plane.

use crate::error::SceneError;
use fogbank_math::{Ray, Vec3};
use serde::{Deserialize, Serialize};

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
    /// Clip planes along the view axis: near ≥ 0, far > near (∞: none).
    near: f32,
    far: f32,
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
            near: 0.0,
            far: f32::INFINITY,
        })
    }

    /// This camera's image mirrored left–right: the image's +x runs along
    /// up × forward instead of forward × up. A left-handed camera frame (pbrt's
    /// `LookAt`) sees this image; no rotation of the camera gives it.
    pub fn mirrored(self) -> Camera {
        Camera {
            right: -self.right,
            ..self
        }
    }

    /// This camera with clip planes at view-axis distances `near` and `far`.
    pub fn with_clip(self, near: f32, far: f32) -> Camera {
        Camera { near, far, ..self }
    }

    /// The clip planes' distances along the view axis (near, far).
    pub fn clip(&self) -> (f32, f32) {
        (self.near, self.far)
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
    /// so ray parameters are world distances. It starts on the near plane.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let sx = (2.0 * x / self.width as f32 - 1.0) * self.tan_half[0];
        let sy = (1.0 - 2.0 * y / self.height as f32) * self.tan_half[1];
        let d = (self.forward + sx * self.right + sy * self.up).normalize();
        if self.near > 0.0 {
            Ray::new(self.origin + d * (self.near / d.dot(self.forward)), d)
        } else {
            Ray::new(self.origin, d)
        }
    }

    /// Where the first segment of a ray from [`Camera::ray`] ends: on the
    /// far plane, (far − near) / cos θ along it (∞ without a far plane).
    #[inline]
    pub fn ray_end(&self, ray: &Ray) -> f32 {
        if self.far.is_finite() {
            (self.far - self.near) / ray.d.dot(self.forward)
        } else {
            f32::INFINITY
        }
    }

    /// Film position (in pixels) where world point `p` appears: the inverse
    /// of [`Camera::ray`]; `None` behind the camera.
    pub fn project(&self, p: Vec3) -> Option<(f32, f32)> {
        let v = p - self.origin;
        let z = v.dot(self.forward);
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        let sx = v.dot(self.right) / (z * self.tan_half[0]);
        let sy = v.dot(self.up) / (z * self.tan_half[1]);
        let (x, y) = (
            0.5 * (sx + 1.0) * self.width as f32,
            0.5 * (1.0 - sy) * self.height as f32,
        );
        (x.is_finite() && y.is_finite()).then_some((x, y))
    }

    /// Film position where the direction `d` (a point at infinity, such as
    /// the environment seen along `d`) appears; `None` behind the camera.
    pub fn project_direction(&self, d: Vec3) -> Option<(f32, f32)> {
        self.project(self.origin + d)
    }
}

/// | key | default | meaning |
/// |---|---|---|
/// | `from`, `to`, `up` | (0,0,2.2), (0,0,0), (0,1,0) | pinhole placement |
/// | `fov` | 40 | field of view in degrees along `fov_axis` (Mitsuba 3's 50 mm lens is 39.6° along x; pbrt-v4's default is 90° along the shorter axis) |
/// | `fov_axis` | `"x"` | `"x"` or `"y"` |
/// | `width`, `height` | 512, 512 | image size in pixels (a preview; pbrt-v4's default is 1280×720, Mitsuba 3's 768×576) |
/// | `near_clip` | 0 | distance of the near clip plane along the view axis: rays start on it |
/// | `mirror` | false | mirror the image left–right (a left-handed camera frame, as pbrt-v4's `LookAt` makes: +x of the image along up × view direction) |
/// | `far_clip` | none | distance of the far clip plane: a camera ray's first segment ends on it (what lies beyond is not seen; the environment is) |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct CameraDesc {
    pub from: [f32; 3],
    pub to: [f32; 3],
    pub up: [f32; 3],
    pub fov: f32,
    pub fov_axis: String,
    pub width: u32,
    pub height: u32,
    #[serde(skip_serializing_if = "is_zero")]
    pub near_clip: f32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub far_clip: Option<f32>,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub mirror: bool,
}

fn is_zero(x: &f32) -> bool {
    *x == 0.0
}

impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc {
            from: [0.0, 0.0, 2.2],
            to: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            fov: 40.0,
            fov_axis: "x".into(),
            width: 512,
            height: 512,
            near_clip: 0.0,
            far_clip: None,
            mirror: false,
        }
    }
}

impl CameraDesc {
    /// The camera, after checking the size, field of view and frame.
    pub fn build(&self) -> Result<Camera, SceneError> {
        let c = self;
        if c.width == 0 || c.height == 0 || c.width > 16384 || c.height > 16384 {
            return Err(SceneError(format!(
                "camera: image size {}×{} outside 1..=16384",
                c.width, c.height
            )));
        }
        if !(c.fov > 0.0 && c.fov < 180.0) {
            return Err(SceneError(format!(
                "camera.fov: {} is outside (0, 180)",
                c.fov
            )));
        }
        let fov_x = match c.fov_axis.as_str() {
            "x" => true,
            "y" => false,
            other => {
                return Err(SceneError(format!(
                    "camera.fov_axis: `{other}` is not x or y"
                )))
            }
        };
        let far = c.far_clip.unwrap_or(f32::INFINITY);
        if !(c.near_clip >= 0.0 && c.near_clip.is_finite() && far > c.near_clip) {
            return Err(SceneError(format!(
                "camera.near_clip {} / far_clip {far}: need 0 ≤ near < far",
                c.near_clip
            )));
        }
        Camera::new(
            Vec3::from(c.from),
            Vec3::from(c.to),
            Vec3::from(c.up),
            c.fov,
            fov_x,
            c.width,
            c.height,
        )
        .map(|cam| {
            let cam = cam.with_clip(c.near_clip, far);
            if c.mirror {
                cam.mirrored()
            } else {
                cam
            }
        })
        .ok_or_else(|| {
            SceneError(
                "camera: `from`, `to` and `up` must span a frame (from ≠ to, up not parallel)"
                    .into(),
            )
        })
    }
}

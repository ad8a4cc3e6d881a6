//! The world an integrator renders: camera, media with their property
//! fields and emission, and lights. Nothing here knows the integrators.

pub mod arrays;
pub mod bitmap;
pub mod blackbody;
pub mod bsdf;
pub mod camera;
pub mod chroma;
mod classified;
pub mod emission;
pub mod field;
pub mod film;
pub mod importance;
pub mod media_bvh;
pub mod medium;
pub mod phase;
pub mod shading;
pub mod surfaces;
pub mod texture;
pub mod transfer;
pub mod velocity;

use crate::error::SceneError;
use crate::lights::sample::LightSelection;
use crate::lights::{Light, LightDesc};
use camera::{Camera, CameraDesc};
use fogbank_math::{Ray, Vec3};
use media_bvh::MediaBvh;
use medium::{MediumDesc, SceneMedium};
use std::path::Path;
use surfaces::{ShapeDesc, Surfaces};

#[derive(Clone, Debug)]
pub struct World {
    pub camera: Camera,
    pub media: Vec<SceneMedium>,
    pub lights: Vec<Light>,
    /// The shapes (`None` without `[[shapes]]`, so media-only scenes take
    /// no surface branch at all).
    pub surfaces: Option<Surfaces>,
    /// Jitter primary rays within the pixel (`render.pixel_jitter`).
    pub pixel_jitter: bool,
    /// How NEE picks lights (`render.light_sampler`).
    pub light_selection: LightSelection,
    /// Seconds between this frame and the previous one (1/`animation.fps`;
    /// 0 for a static scene): how far media move along their velocity.
    pub frame_dt: f32,
    /// Over the media's world boxes when there are many (instances).
    media_bvh: Option<MediaBvh>,
}

/// From this many media on, rays find theirs through a BVH.
pub const MEDIA_BVH_MIN: usize = 9;

impl World {
    /// Builds camera, media, lights and shapes (whose emitting triangles
    /// join the lights), resolving files against `base`.
    pub fn build(
        camera: &CameraDesc,
        media: &[MediumDesc],
        lights: &[LightDesc],
        shapes: &[ShapeDesc],
        pixel_jitter: bool,
        light_selection: LightSelection,
        base: &Path,
    ) -> Result<World, SceneError> {
        let media: Vec<SceneMedium> = media
            .iter()
            .enumerate()
            .map(|(i, m)| m.build_instances(i, base))
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .flatten()
            .collect();
        let media_bvh = (media.len() >= MEDIA_BVH_MIN).then(|| {
            MediaBvh::build(
                &media
                    .iter()
                    .map(|m| m.medium.world_bounds())
                    .collect::<Vec<_>>(),
            )
        });
        let mut lights: Vec<Light> = lights
            .iter()
            .enumerate()
            .map(|(i, l)| l.build(i, base))
            .collect::<Result<_, _>>()?;
        let camera = camera.build()?;
        let surfaces = if shapes.is_empty() {
            None
        } else {
            Some(Surfaces::build(
                shapes,
                base,
                &media,
                camera.origin,
                &mut lights,
            )?)
        };
        Ok(World {
            camera,
            media,
            media_bvh,
            lights,
            surfaces,
            pixel_jitter,
            light_selection,
            frame_dt: 0.0,
        })
    }

    /// Calls `visit(i)` for the media the ray may cross within
    /// `[0, t_max()]`: every medium in order when there are few, else those
    /// whose boxes it crosses, nearest first (`t_max` is re-read, so a
    /// shortened ray prunes the rest).
    pub fn media_along(&self, ray: &Ray, t_max: impl FnMut() -> f32, mut visit: impl FnMut(usize)) {
        match &self.media_bvh {
            Some(b) if b.len() == self.media.len() => b.visit(ray, t_max, visit),
            _ => (0..self.media.len()).for_each(&mut visit),
        }
    }

    /// The lights of `[[lights]]` with their indices: all but the emitting
    /// shapes' (triangles, spheres, disks), which follow them (so a scene
    /// with thousands of emitters does not walk them looking for its
    /// environment).
    pub fn scene_lights(&self) -> impl Iterator<Item = (usize, &Light)> {
        (self.lights.iter().enumerate()).take_while(|(_, l)| !l.is_shape())
    }

    /// Whether medium `i` is present for a ray in bounded medium `current`
    /// (media that no shape bounds always are).
    #[inline]
    pub fn medium_active(&self, i: usize, current: Option<usize>) -> bool {
        match &self.surfaces {
            None => true,
            Some(s) => current == Some(i) || !s.bounds_medium(i),
        }
    }

    /// Whether point `p`, reached by a ray now in bounded medium `current`,
    /// lies in a medium: the bounded one, or the box of a medium that
    /// exists for the ray there.
    pub fn in_medium(&self, current: Option<usize>, p: Vec3) -> bool {
        current.is_some()
            || self.media.iter().enumerate().any(|(i, m)| {
                let q = m.medium.world_to_index.transform_point3(p.as_dvec3());
                let d = m.medium.dims();
                self.medium_active(i, current) && (0..3).all(|k| q[k] >= 0.0 && q[k] <= d[k] as f64)
            })
    }

    /// Whether a camera ray whose first segment ended on the far clip plane
    /// at `t_far`, in bounded medium `current`, is lost: Mitsuba's volpath
    /// takes a medium to go on beyond the far plane (its transmittance to
    /// there over the pdf of passing it is 0), so such a path brings
    /// nothing; outside any medium the ray sees the environment.
    pub fn lost_at_far_clip(&self, current: Option<usize>, ray: &Ray, t_far: f32) -> bool {
        t_far.is_finite() && self.in_medium(current, ray.at(t_far))
    }

    /// Half the diagonal of the media's and shapes' world bounds (1 with
    /// neither): the scene radius of the light-power proxy.
    pub fn radius(&self) -> f32 {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        let shapes = self.surfaces.as_ref().map(|s| s.bounds());
        for b in self
            .media
            .iter()
            .map(|m| m.medium.world_bounds())
            .chain(shapes)
        {
            lo = lo.min(b.min);
            hi = hi.max(b.max);
        }
        if lo.x <= hi.x {
            0.5 * (hi - lo).length()
        } else {
            1.0
        }
    }
    /// Whether the camera's far clip plane cuts the scene: a medium's box
    /// or the shapes' bounds reach it along the view axis. Only then does
    /// ending camera rays on it change the image.
    pub fn far_clip_cuts(&self) -> bool {
        let (_, far) = self.camera.clip();
        if !far.is_finite() {
            return false;
        }
        let (origin, forward, ..) = self.camera.basis();
        let boxes = self.media.iter().map(|m| m.medium.world_bounds());
        let mut boxes = boxes.chain(self.surfaces.as_ref().map(|s| s.bounds()));
        boxes.any(|b| {
            (0..8).any(|c| {
                let corner = Vec3::new(
                    if c & 1 != 0 { b.max.x } else { b.min.x },
                    if c & 2 != 0 { b.max.y } else { b.min.y },
                    if c & 4 != 0 { b.max.z } else { b.min.z },
                );
                (corner - origin).dot(forward) >= far
            })
        })
    }
}

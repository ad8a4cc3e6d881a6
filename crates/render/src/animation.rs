//! Frame sequences (`[animation]`): a frame count and rate, keyframes for
//! the camera, each medium's placement and each light, and per-frame files
//! (`density = { vdb = "plume_{frame:04}.vdb" }`). A frame's scene is the
//! scene with every keyed value interpolated linearly between the keys
//! around the frame (held before the first and after the last) and every
//! `{frame}` / `{frame:0N}` in a medium's file names replaced by the frame
//! number; a procedural plume's `time` advances by frame/fps.
//!
//! | key | default | meaning |
//! |---|---|---|
//! | `frames` | — | frame count (frames are 0 … frames − 1) |
//! | `fps` | 24 | frame rate (velocities are per second) |
//! | `[[animation.camera]]` | none | `frame` and any of `from`, `to`, `up`, `fov` |
//! | `[[animation.media]]` | none | `medium` (index), `frame` and any of `translate`, `rotate` (`[x, y, z, degrees]`), `scale` |
//! | `[[animation.lights]]` | none | `light` (index), `frame` and any of `position` (point, spot), `direction` (directional, spot), `rotate` (envmap, `[x, y, z, degrees]`), `intensity` / `irradiance` / `radiance` (RGB, by light type) |

use crate::error::SceneError;
use crate::lights::LightDesc;
use crate::world::camera::CameraDesc;
use crate::world::field::FieldDesc;
use crate::world::medium::{MediumDesc, ScaleDesc};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AnimationDesc {
    pub frames: u32,
    #[serde(default = "default_fps")]
    pub fps: f32,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub camera: Vec<CameraKey>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub media: Vec<MediumKey>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<LightKey>,
}

fn default_fps() -> f32 {
    24.0
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    pub frame: u32,
    pub from: Option<[f32; 3]>,
    pub to: Option<[f32; 3]>,
    pub up: Option<[f32; 3]>,
    pub fov: Option<f32>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MediumKey {
    pub medium: usize,
    pub frame: u32,
    pub translate: Option<[f32; 3]>,
    pub rotate: Option<[f32; 4]>,
    pub scale: Option<ScaleDesc>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LightKey {
    pub light: usize,
    pub frame: u32,
    pub position: Option<[f32; 3]>,
    pub direction: Option<[f32; 3]>,
    pub rotate: Option<[f32; 4]>,
    pub intensity: Option<[f32; 3]>,
    pub irradiance: Option<[f32; 3]>,
    pub radiance: Option<[f32; 3]>,
}

/// Linear interpolation of the keyed values `keys` = (frame, value) at
/// `frame`: held before the first key and after the last; `None` without
/// keys. Keys are in frame order (checked by [`AnimationDesc::check`]).
fn interpolate<const N: usize>(keys: &[(u32, [f32; N])], frame: u32) -> Option<[f32; N]> {
    let first = keys.first()?;
    if frame <= first.0 {
        return Some(first.1);
    }
    for w in keys.windows(2) {
        let ((f0, a), (f1, b)) = (w[0], w[1]);
        if frame <= f1 {
            let s = if f1 > f0 {
                (frame - f0) as f32 / (f1 - f0) as f32
            } else {
                1.0
            };
            return Some(std::array::from_fn(|i| a[i] + s * (b[i] - a[i])));
        }
    }
    keys.last().map(|k| k.1)
}

/// The keys of `items` for which `get` gives a value, as (frame, value).
fn keyed<T, const N: usize>(
    items: &[T],
    frame_of: impl Fn(&T) -> u32,
    get: impl Fn(&T) -> Option<[f32; N]>,
) -> Vec<(u32, [f32; N])> {
    items
        .iter()
        .filter_map(|k| get(k).map(|v| (frame_of(k), v)))
        .collect()
}

/// `path` with `{frame}` replaced by `frame` and `{frame:0N}` by `frame`
/// padded with zeros to N digits.
pub fn frame_path(path: &str, frame: u32) -> String {
    let mut out = path.replace("{frame}", &frame.to_string());
    while let Some(start) = out.find("{frame:0") {
        let Some(len) = out[start..].find('}') else {
            break;
        };
        let width: usize = out[start + 8..start + len].parse().unwrap_or(0);
        out.replace_range(start..start + len + 1, &format!("{frame:0width$}"));
    }
    out
}

/// `f` at `frame`: per-frame file names; a procedural plume's `time`
/// advances by frame/fps.
fn frame_field(f: &mut FieldDesc, frame: u32, fps: f32) {
    for p in f.files.paths_mut() {
        *p = frame_path(p, frame);
    }
    if f.procedural.as_deref() == Some("plume") {
        f.time = Some(f.time.unwrap_or(0.0) + frame as f32 / fps);
    }
}

impl AnimationDesc {
    /// Checks frame ranges, key order and indices against the scene's
    /// media and lights; errors name the key.
    pub fn check(&self, media: &[MediumDesc], lights: &[LightDesc]) -> Result<(), SceneError> {
        if self.frames == 0 || self.frames > 10_000_000 {
            return Err(SceneError(format!(
                "animation.frames: {} is outside 1..=10000000",
                self.frames
            )));
        }
        if !(self.fps > 0.0 && self.fps.is_finite()) {
            return Err(SceneError(format!(
                "animation.fps: must be positive, got {}",
                self.fps
            )));
        }
        let last = self.frames - 1;
        check_frames("camera", last, self.camera.iter().map(|k| (k.frame, 0)))?;
        check_frames(
            "media",
            last,
            self.media.iter().map(|k| (k.frame, k.medium)),
        )?;
        check_frames(
            "lights",
            last,
            self.lights.iter().map(|k| (k.frame, k.light)),
        )?;
        for (i, k) in self.media.iter().enumerate() {
            if k.medium >= media.len() {
                return Err(SceneError(format!(
                    "animation.media.{i}.medium: {} is not a medium index (the scene has {})",
                    k.medium,
                    media.len()
                )));
            }
        }
        for (i, k) in self.lights.iter().enumerate() {
            let Some(l) = lights.get(k.light) else {
                return Err(SceneError(format!(
                    "animation.lights.{i}.light: {} is not a light index (the scene has {})",
                    k.light,
                    lights.len()
                )));
            };
            check_light_key(i, k, l)?;
        }
        Ok(())
    }

    /// The camera at `frame`.
    pub fn camera(&self, base: &CameraDesc, frame: u32) -> CameraDesc {
        let k = &self.camera;
        let fr = |c: &CameraKey| c.frame;
        let mut c = base.clone();
        if let Some(v) = interpolate(&keyed(k, fr, |c| c.from), frame) {
            c.from = v;
        }
        if let Some(v) = interpolate(&keyed(k, fr, |c| c.to), frame) {
            c.to = v;
        }
        if let Some(v) = interpolate(&keyed(k, fr, |c| c.up), frame) {
            c.up = v;
        }
        if let Some([v]) = interpolate(&keyed(k, fr, |c| c.fov.map(|f| [f])), frame) {
            c.fov = v;
        }
        c
    }

    /// Medium `index` at `frame`: placement keys and per-frame files.
    pub fn medium(&self, base: &MediumDesc, index: usize, frame: u32) -> MediumDesc {
        let keys: Vec<&MediumKey> = self.media.iter().filter(|k| k.medium == index).collect();
        let fr = |k: &&MediumKey| k.frame;
        let mut m = base.clone();
        if let Some(v) = interpolate(&keyed(&keys, fr, |k| k.translate), frame) {
            m.to_world.translate = Some(v);
        }
        if let Some(v) = interpolate(&keyed(&keys, fr, |k| k.rotate), frame) {
            m.to_world.rotate = Some(v);
        }
        let scale = |k: &&MediumKey| match k.scale {
            Some(ScaleDesc::Uniform(s)) => Some([s; 3]),
            Some(ScaleDesc::PerAxis(s)) => Some(s),
            None => None,
        };
        if let Some(v) = interpolate(&keyed(&keys, fr, scale), frame) {
            m.to_world.scale = Some(ScaleDesc::PerAxis(v));
        }
        frame_field(&mut m.density, frame, self.fps);
        if let Some(g) = m.albedo_grid.as_mut() {
            frame_field(g, frame, self.fps);
        }
        if let Some(e) = m.emission.as_mut() {
            for g in [&mut e.grid, &mut e.temperature].into_iter().flatten() {
                frame_field(g, frame, self.fps);
            }
        }
        if let Some(v) = m.velocity.as_mut() {
            for f in [&mut v.vdb, &mut v.nvdb].into_iter().flatten() {
                *f = frame_path(f, frame);
            }
        }
        m
    }

    /// Light `index` at `frame`.
    pub fn light(&self, base: &LightDesc, index: usize, frame: u32) -> LightDesc {
        let keys: Vec<&LightKey> = self.lights.iter().filter(|k| k.light == index).collect();
        let fr = |k: &&LightKey| k.frame;
        let at = |get: &dyn Fn(&LightKey) -> Option<[f32; 3]>| {
            interpolate(&keyed(&keys, fr, |k| get(k)), frame)
        };
        let mut l = base.clone();
        match &mut l {
            LightDesc::Constant { radiance } => {
                *radiance = at(&|k| k.radiance).unwrap_or(*radiance);
            }
            LightDesc::Envmap { rotate, .. } => {
                if let Some(v) = interpolate(&keyed(&keys, fr, |k| k.rotate), frame) {
                    *rotate = Some(v);
                }
            }
            LightDesc::Sky { .. } => {}
            LightDesc::Point {
                position,
                intensity,
            } => {
                *position = at(&|k| k.position).unwrap_or(*position);
                *intensity = at(&|k| k.intensity).unwrap_or(*intensity);
            }
            LightDesc::Directional {
                direction,
                irradiance,
            } => {
                *direction = at(&|k| k.direction).unwrap_or(*direction);
                *irradiance = at(&|k| k.irradiance).unwrap_or(*irradiance);
            }
            LightDesc::Spot {
                position,
                direction,
                intensity,
                ..
            } => {
                *position = at(&|k| k.position).unwrap_or(*position);
                *direction = at(&|k| k.direction).unwrap_or(*direction);
                *intensity = at(&|k| k.intensity).unwrap_or(*intensity);
            }
        }
        l
    }
}

fn light_type(l: &LightDesc) -> &'static str {
    match l {
        LightDesc::Constant { .. } => "constant",
        LightDesc::Envmap { .. } => "envmap",
        LightDesc::Sky { .. } => "sky",
        LightDesc::Point { .. } => "point",
        LightDesc::Directional { .. } => "directional",
        LightDesc::Spot { .. } => "spot",
    }
}

/// Key frames of animation table `table` (frame, animated index): each
/// frame in 0..=`last`, and increasing per animated index.
fn check_frames(
    table: &str,
    last: u32,
    frames: impl Iterator<Item = (u32, usize)>,
) -> Result<(), SceneError> {
    let mut previous: std::collections::HashMap<usize, u32> = Default::default();
    for (i, (f, target)) in frames.enumerate() {
        if f > last {
            return Err(SceneError(format!(
                "animation.{table}.{i}.frame: {f} is outside 0..={last}"
            )));
        }
        if let Some(&p) = previous.get(&target) {
            if f <= p {
                return Err(SceneError(format!(
                    "animation.{table}.{i}.frame: keys must be in increasing frame order ({f} after {p})"
                )));
            }
        }
        previous.insert(target, f);
    }
    Ok(())
}

/// Light key `animation.lights.{i}` animates only what its light `l` has.
fn check_light_key(i: usize, k: &LightKey, l: &LightDesc) -> Result<(), SceneError> {
    let allowed: &[&str] = match l {
        LightDesc::Constant { .. } => &["radiance"],
        LightDesc::Envmap { .. } => &["rotate"],
        LightDesc::Sky { .. } => &[],
        LightDesc::Point { .. } => &["position", "intensity"],
        LightDesc::Directional { .. } => &["direction", "irradiance"],
        LightDesc::Spot { .. } => &["position", "direction", "intensity"],
    };
    let given = [
        ("position", k.position.is_some()),
        ("direction", k.direction.is_some()),
        ("rotate", k.rotate.is_some()),
        ("intensity", k.intensity.is_some()),
        ("irradiance", k.irradiance.is_some()),
        ("radiance", k.radiance.is_some()),
    ];
    if let Some((key, _)) = given.iter().find(|(key, g)| *g && !allowed.contains(key)) {
        return Err(SceneError(format!(
            "animation.lights.{i}.{key}: light {} is a {} light, which animates {}",
            k.light,
            light_type(l),
            allowed.join(", ")
        )));
    }
    Ok(())
}

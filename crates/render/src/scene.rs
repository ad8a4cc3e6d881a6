//! A scene: its description (the TOML format), the world built from it and
//! the integrator that renders it. Relative paths resolve against the scene
//! file's folder.

use crate::animation::AnimationDesc;
use crate::error::SceneError;
use crate::integrators::{IntegratorDesc, IntegratorKind, REGISTRY};
use crate::lights::sample::LightSelection;
use crate::lights::LightDesc;
use crate::overrides::{apply_override, parse_value};
use crate::world::camera::CameraDesc;
use crate::world::medium::MediumDesc;
use crate::world::surfaces::ShapeDesc;
use crate::world::World;
use fogbank_image::{ToneCurve, ToneMapping};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The TOML scene format, as plain serde structs. Every table denies
/// unknown keys, so a typo is an error naming the key rather than a silently
/// ignored setting; `[integrator]` takes the keys of its `type` only. `--set
/// a.b.0.c=VALUE` edits the parsed document before these structs are built.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    #[serde(default)]
    pub camera: CameraDesc,
    #[serde(default)]
    pub media: Vec<MediumDesc>,
    #[serde(default)]
    pub lights: Vec<LightDesc>,
    /// Surfaces (see [`crate::world::surfaces`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shapes: Vec<ShapeDesc>,
    #[serde(default)]
    pub integrator: IntegratorDesc,
    #[serde(default)]
    pub render: RenderDesc,
    /// A frame sequence (see [`crate::animation`]); without it the scene is
    /// one static frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<AnimationDesc>,
}

/// | key | default | meaning |
/// |---|---|---|
/// | `spp` | 16 | samples per pixel |
/// | `seed` | 0 | scene seed; the image is a function of scene, seed and spp |
/// | `pixel_jitter` | true | jitter primary rays within pixels (false: pixel centres): a one-pixel box filter, where pbrt-v4 and Mitsuba 3 default to a Gaussian, so that each pixel stays an independent estimate (per-pixel statistics, z-tests, shards merged bit for bit) |
/// | `exposure` | 0 | stops applied before the tone curve, for PNG output and the viewer |
/// | `tonemap` | `linear` | tone curve for PNG and the viewer: `linear`, `aces`, `agx` (see `fogbank_image::tonemap`); EXR stays linear |
/// | `light_sampler` | `auto` | how NEE picks lights: `power` (a CDF by power), `bvh` (emitting triangles through a light BVH by their importance at the point, pbrt-v4's default), `auto` (`bvh` from 1024 emitting triangles on) |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct RenderDesc {
    pub spp: u32,
    pub seed: u32,
    /// Jitter primary rays within the pixel (antialiasing); `false` sends
    /// them through pixel centres, so per-pixel statistics compare against
    /// a single exact value (`fogbank stats` does this).
    pub pixel_jitter: bool,
    pub exposure: f32,
    pub tonemap: ToneCurve,
    #[serde(skip_serializing_if = "LightSelection::is_auto")]
    pub light_sampler: LightSelection,
}

impl RenderDesc {
    /// How PNG files and the viewer display this scene's linear image.
    pub fn tone_mapping(&self) -> ToneMapping {
        ToneMapping {
            exposure: self.exposure,
            curve: self.tonemap,
        }
    }
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            spp: 16,
            seed: 0,
            pixel_jitter: true,
            exposure: 0.0,
            tonemap: ToneCurve::Linear,
            light_sampler: LightSelection::Auto,
        }
    }
}

/// The built-in default scene: a procedural cumulus lit by a gradient sky
/// and the sun, multiple scattering (`volpath`) with forward-scattering HG,
/// tone-mapped with AgX. Its spp and resolution are chosen so that it
/// renders in about 20 s on a 2-core machine (README). Track-length NEE:
/// in this thick cloud its binary estimate stops at the first collision,
/// so it affords 1.7× the spp of ratio tracking in the same time and
/// reaches 1.28× lower MSE (200×150, 5 s budgets, against 1536 spp). The transmittance
/// view that used to be the default is `scenes/transmittance.toml`.
pub const DEFAULT_SCENE: &str = r#"
[camera]
from = [0.0, -0.5, 2.1]
to = [0.0, 0.08, 0.0]
fov = 38.0
width = 400
height = 300

[[media]]
density = { procedural = "cloud", resolution = 160, seed = 7 }
sigma_t_scale = 25.0
albedo = [0.97, 0.97, 0.97]
phase = { type = "hg", g = 0.6 }
filter = "trilinear"

[[lights]]
type = "sky"
zenith = [0.10, 0.25, 0.75]
horizon = [0.65, 0.78, 0.95]
ground = [0.25, 0.23, 0.2]

[[lights]]
type = "directional"
direction = [-0.8, -0.45, 0.25]
irradiance = [14.0, 13.0, 11.5]

[integrator]
type = "volpath"
estimator = "track_length"
max_depth = 64

[render]
spp = 160
seed = 0
tonemap = "agx"
"#;

/// The transmittance view of the same cumulus (`scenes/transmittance.toml`):
/// the built-in scene of `stats` and `converge`, whose exact references
/// exist for transmittance images.
pub const TRANSMITTANCE_SCENE: &str = include_str!("../../../scenes/transmittance.toml");

/// `desc` is what the scene was built from; the world and the integrator
/// are what renders, so a change after building goes to them.
#[derive(Clone, Debug)]
pub struct Scene {
    pub desc: SceneDesc,
    pub world: World,
    pub integrator: IntegratorKind,
    /// The frame the world shows (0 for a static scene).
    pub frame: u32,
    /// The folder relative file names resolve against.
    pub base: PathBuf,
}

/// A scene reads as its world (`scene.media`, `scene.camera`, …).
impl std::ops::Deref for Scene {
    type Target = World;
    fn deref(&self) -> &World {
        &self.world
    }
}

impl std::ops::DerefMut for Scene {
    fn deref_mut(&mut self) -> &mut World {
        &mut self.world
    }
}

impl Scene {
    /// The scene (frame 0 of an animation).
    pub fn build(desc: SceneDesc, base: &Path) -> Result<Scene, SceneError> {
        Scene::build_frame(desc, base, 0)
    }

    /// Frame `frame` of the scene's animation (a static scene has frame 0
    /// only); `desc` stays the whole description.
    pub fn build_frame(desc: SceneDesc, base: &Path, frame: u32) -> Result<Scene, SceneError> {
        let world = match &desc.animation {
            None if frame > 0 => {
                return Err(SceneError(format!(
                    "frame {frame}: the scene has no [animation]"
                )))
            }
            None => World::build(
                &desc.camera,
                &desc.media,
                &desc.lights,
                &desc.shapes,
                desc.render.pixel_jitter,
                desc.render.light_sampler,
                base,
            )?,
            Some(a) => {
                a.check(&desc.media, &desc.lights)?;
                if frame >= a.frames {
                    return Err(SceneError(format!(
                        "frame {frame}: the animation has frames 0..={}",
                        a.frames - 1
                    )));
                }
                let media: Vec<MediumDesc> = (desc.media.iter().enumerate())
                    .map(|(i, m)| a.medium(m, i, frame))
                    .collect();
                let lights: Vec<LightDesc> = (desc.lights.iter().enumerate())
                    .map(|(i, l)| a.light(l, i, frame))
                    .collect();
                let mut world = World::build(
                    &a.camera(&desc.camera, frame),
                    &media,
                    &lights,
                    &desc.shapes,
                    desc.render.pixel_jitter,
                    desc.render.light_sampler,
                    base,
                )
                .map_err(|SceneError(e)| SceneError(format!("frame {frame}: {e}")))?;
                world.frame_dt = 1.0 / a.fps;
                world
            }
        };
        let integrator = desc.integrator.build(&world)?;
        Ok(Scene {
            desc,
            world,
            integrator,
            frame,
            base: base.to_path_buf(),
        })
    }

    /// Another frame of this scene's animation.
    pub fn at_frame(&self, frame: u32) -> Result<Scene, SceneError> {
        Scene::build_frame(self.desc.clone(), &self.base, frame)
    }

    /// One sample of pixel `(x, y)` with sample index `key.sample`.
    #[inline]
    pub fn sample_pixel(
        &self,
        x: u32,
        y: u32,
        key: fogbank_math::SampleKey,
    ) -> crate::integrators::shared::PixelSample {
        self.integrator.sample_pixel(&self.world, x, y, key)
    }
}

/// Parses scene TOML, applies `KEY=VALUE` overrides, and deserialises.
pub fn parse_scene(
    text: &str,
    origin: &str,
    overrides: &[String],
) -> Result<SceneDesc, SceneError> {
    if overrides.is_empty() {
        // Straight from the text, so error line numbers point into the file.
        return toml::from_str(text).map_err(|e| SceneError(format!("{origin}: {e}")));
    }
    let mut doc: toml::Table =
        toml::from_str(text).map_err(|e| SceneError(format!("{origin}: {e}")))?;
    let file_type = integrator_type(&doc);
    let mut set_keys = Vec::new();
    for o in overrides {
        let (key, value) = o
            .split_once('=')
            .ok_or_else(|| SceneError(format!("--set {o}: expected KEY=VALUE")))?;
        apply_override(&mut doc, key.trim(), parse_value(value.trim()))?;
        set_keys.push(key.trim().to_string());
    }
    drop_keys_of_the_replaced_integrator(&mut doc, &file_type, &set_keys);
    // Round-trip through text so error messages carry toml's key paths.
    let text = toml::to_string(&doc).map_err(|e| SceneError(format!("{origin}: {e}")))?;
    toml::from_str(&text).map_err(|e| SceneError(format!("{origin} (after --set overrides): {e}")))
}

/// `[integrator] type` of a parsed document (`transmittance` when absent).
fn integrator_type(doc: &toml::Table) -> String {
    doc.get("integrator")
        .and_then(|i| i.get("type"))
        .and_then(|t| t.as_str())
        .unwrap_or("transmittance")
        .to_string()
}

/// `--set integrator.type=direct` on a scene written for `volpath`: the
/// file's parameters of the replaced integrator that the new one does not
/// take (`max_depth`) are dropped, so switching integrators from the
/// command line works on any scene. A key given with `--set` is never
/// dropped: a misplaced one is still refused.
fn drop_keys_of_the_replaced_integrator(
    doc: &mut toml::Table,
    file_type: &str,
    set_keys: &[String],
) {
    let new_type = integrator_type(doc);
    if new_type == file_type {
        return;
    }
    let params_of = |ty: &str| {
        REGISTRY
            .iter()
            .find(|(n, _)| *n == ty)
            .map(|(_, p)| p.iter().map(|p| p.key).collect::<Vec<_>>())
            .unwrap_or_default()
    };
    let (old, new) = (params_of(file_type), params_of(&new_type));
    if let Some(toml::Value::Table(t)) = doc.get_mut("integrator") {
        t.retain(|k, _| {
            !old.contains(&k)
                || new.contains(&k)
                || set_keys.iter().any(|s| s == &format!("integrator.{k}"))
        });
    }
}

impl SceneDesc {
    pub fn default_scene() -> SceneDesc {
        toml::from_str(DEFAULT_SCENE).expect("the built-in scene parses")
    }
}

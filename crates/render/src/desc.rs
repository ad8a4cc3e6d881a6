//! The TOML scene format, as plain serde structs.
//!
//! Every table denies unknown keys, so a typo is an error naming the key
//! rather than a silently ignored setting. `--set a.b.0.c=VALUE` edits the
//! parsed document before these structs are built (see [`apply_override`]).

use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    #[serde(default)]
    pub camera: CameraDesc,
    #[serde(default)]
    pub media: Vec<MediumDesc>,
    #[serde(default)]
    pub lights: Vec<LightDesc>,
    #[serde(default)]
    pub integrator: IntegratorDesc,
    #[serde(default)]
    pub render: RenderDesc,
}

/// | key | default | meaning |
/// |---|---|---|
/// | `from`, `to`, `up` | (0,0,2.2), (0,0,0), (0,1,0) | pinhole placement |
/// | `fov` | 40 | field of view in degrees along `fov_axis` |
/// | `fov_axis` | `"x"` | `"x"` or `"y"` |
/// | `width`, `height` | 512, 512 | image size in pixels |
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
        }
    }
}

/// | key | default | meaning |
/// |---|---|---|
/// | `density` | — | data source, see [`DensityDesc`] |
/// | `sigma_t_scale` | 1 | σ_t = scale · density (per world unit) |
/// | `albedo` | (0.8, 0.8, 0.8) | single-scattering albedo σ_s/σ_t, each channel in [0, 1] |
/// | `albedo_grid` | none | a grid (same keys as `density`, placed like it) multiplying `albedo`; a 3-channel `.vol` without `channel` gives RGB; values clamp to [0, 1] |
/// | `emission` | none | volumetric emission, see [`EmissionDesc`] |
/// | `phase` | `{ type = "hg", g = 0 }` | phase function |
/// | `to_world` | identity | placement after the file's own transform |
/// | `filter` | `"stochastic_trilinear"` | `nearest`, `trilinear`, `stochastic_trilinear` |
/// | `supervoxel` | 16 | super-voxel edge in voxels |
/// | `precision` | `"f16"` | voxel storage, `f16` or `f32` |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MediumDesc {
    pub density: DensityDesc,
    #[serde(default = "one")]
    pub sigma_t_scale: f32,
    #[serde(default = "default_albedo")]
    pub albedo: [f32; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo_grid: Option<DensityDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emission: Option<EmissionDesc>,
    #[serde(default)]
    pub phase: PhaseDesc,
    #[serde(default)]
    pub to_world: TransformDesc,
    #[serde(default = "default_filter")]
    pub filter: String,
    #[serde(default = "default_supervoxel")]
    pub supervoxel: u32,
    #[serde(default = "default_precision")]
    pub precision: String,
}

fn one() -> f32 {
    1.0
}
fn default_albedo() -> [f32; 3] {
    [0.8; 3]
}
fn default_filter() -> String {
    "stochastic_trilinear".into()
}
fn default_supervoxel() -> u32 {
    16
}
fn default_precision() -> String {
    "f16".into()
}

/// Exactly one source key: `vdb`, `vol`, `raw` or `procedural`.
///
/// | source | further keys |
/// |---|---|
/// | `vdb = "f.vdb"` | `grid` (default `density`, else the first float grid), `level_set` = `"fog"` (default) or `"raw"` |
/// | `vol = "f.vol"` | `channel` (default 0) |
/// | `raw = "f.raw"` | `dims = [x, y, z]`, `type = "u8"/"u16"/"f32"` (or from a `name_XxYxZ_uint8.raw` file name) |
/// | `procedural = "cloud"` | `resolution` (128), `seed` (7) |
/// | `procedural = "constant"/"ramp"/"sinusoid"/"slabs"/"sphere"/"empty"` | `resolution`, `value`, `gradient`, `amplitude`, `frequency`, `phase`, `count`, `width`, `axis`, `radius` |
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DensityDesc {
    pub vdb: Option<String>,
    pub grid: Option<String>,
    pub level_set: Option<String>,
    pub vol: Option<String>,
    pub channel: Option<u32>,
    pub raw: Option<String>,
    pub dims: Option<[u32; 3]>,
    #[serde(rename = "type")]
    pub ty: Option<String>,
    pub procedural: Option<String>,
    pub resolution: Option<u32>,
    pub seed: Option<u64>,
    pub value: Option<f32>,
    pub gradient: Option<[f32; 3]>,
    pub amplitude: Option<f32>,
    pub frequency: Option<[f32; 3]>,
    pub phase: Option<f32>,
    pub count: Option<u32>,
    pub width: Option<f32>,
    pub axis: Option<usize>,
    /// `procedural = "sphere"`: ball radius in units of the cube (≤ ½).
    pub radius: Option<f32>,
}

/// Emitted radiance L_e of a medium. Following pbrt-v4, a medium emits
/// where it absorbs: the radiance gained along a ray is ∫ T σ_a L_e dt with
/// σ_a = σ_t (1 − albedo), so emission needs albedo < 1 and vanishes where
/// the density does.
///
/// | key | default | meaning |
/// |---|---|---|
/// | `color` | (1, 1, 1) | RGB radiance (or tint of the blackbody) |
/// | `scale` | 1 | multiplies the radiance |
/// | `grid` | none | a grid (same keys as `density`) multiplying `color` |
/// | `temperature` | none | a temperature grid in kelvin: L_e = scale · color · blackbody(T), the Planck spectrum normalised to peak 1 (as pbrt-v4) in linear sRGB |
/// | `temperature_scale`, `temperature_offset` | 1, 0 | T = (grid − offset) · scale; T ≤ 100 K emits nothing |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EmissionDesc {
    #[serde(default = "white")]
    pub color: [f32; 3],
    #[serde(default = "one")]
    pub scale: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<DensityDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature: Option<DensityDesc>,
    #[serde(default = "one")]
    pub temperature_scale: f32,
    #[serde(default)]
    pub temperature_offset: f32,
}

fn white() -> [f32; 3] {
    [1.0; 3]
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PhaseDesc {
    #[serde(rename = "type")]
    pub ty: String,
    #[serde(default)]
    pub g: f32,
}

impl Default for PhaseDesc {
    fn default() -> Self {
        PhaseDesc {
            ty: "hg".into(),
            g: 0.0,
        }
    }
}

/// Applied as translate · rotate · scale.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TransformDesc {
    pub translate: Option<[f32; 3]>,
    /// Uniform (`scale = 2`) or per axis (`scale = [1, 2, 1]`).
    pub scale: Option<ScaleDesc>,
    /// Axis and angle in degrees: `[x, y, z, degrees]`.
    pub rotate: Option<[f32; 4]>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(f32),
    PerAxis([f32; 3]),
}

/// | type | keys |
/// |---|---|
/// | `constant` | `radiance` (RGB) |
/// | `envmap` | `file`, `scale` (1) |
/// | `point` | `position`, `intensity` (RGB) |
/// | `directional` | `direction` (towards which light travels), `irradiance` (RGB) |
/// | `spot` | `position`, `direction`, `intensity` (RGB), `cone_angle` (30°), `falloff_start` (25°) |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LightDesc {
    Constant {
        radiance: [f32; 3],
    },
    Envmap {
        file: String,
        #[serde(default = "one")]
        scale: f32,
        /// Rotation as `[x, y, z, degrees]` (axis and angle).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rotate: Option<[f32; 4]>,
    },
    Point {
        position: [f32; 3],
        intensity: [f32; 3],
    },
    Directional {
        direction: [f32; 3],
        irradiance: [f32; 3],
    },
    /// A point light emitting into a cone around `direction`: full intensity
    /// within `falloff_start` degrees of the axis, smoothly down to zero at
    /// `cone_angle` degrees (pbrt-v4's spotlight).
    Spot {
        position: [f32; 3],
        direction: [f32; 3],
        intensity: [f32; 3],
        #[serde(default = "default_cone")]
        cone_angle: f32,
        #[serde(default = "default_falloff")]
        falloff_start: f32,
    },
}

fn default_cone() -> f32 {
    30.0
}
fn default_falloff() -> f32 {
    25.0
}

/// | key | default | meaning |
/// |---|---|---|
/// | `type` | `"transmittance"` | the integrator: `transmittance`, `volpath` or `point_mis` |
/// | `estimator` | `"ratio_tracking"` | transmittance estimator by name (`fogbank estimators`); for `volpath` the NEE estimator, for `point_mis` the light ray's |
/// | `distance_sampler`, `max_depth`, `rr_depth`, `preset` | delta_tracking, 64, 3, – | `volpath` only |
/// | `strategy` | `"mis_jackknife"` | `point_mis` only: `free_flight`, `equiangular`, `mis_miller`, `mis_naive`, `mis_jackknife`, `mis_jackknife_biased` |
/// | `mis_samples` | 10 | `point_mis` only: lookups N per optical-depth estimate of the MIS weights |
/// | `background` | (1, 1, 1) | radiance behind the media; the image is T · background |
/// | `samples`, `mode`, `step`, `jitter`, `mult`, `doubled`, `clip` | per estimator | estimator options (`fogbank estimators`) |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct IntegratorDesc {
    #[serde(rename = "type")]
    pub ty: String,
    pub estimator: String,
    pub background: [f32; 3],
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mode: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jitter: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mult: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub doubled: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clip: Option<bool>,
    /// `volpath`: free-flight sampler (`delta_tracking`, `decomposition_tracking`, `regular_tracking`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_sampler: Option<String>,
    /// `volpath`: longest path (default 64).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<u32>,
    /// `volpath`: first bounce with Russian roulette (default 3).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rr_depth: Option<u32>,
    /// `volpath`: `baseline` = decomposition tracking + residual ratio tracking (seed 002's baseline).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// `point_mis`: distance-sampling strategy (default `mis_jackknife`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strategy: Option<String>,
    /// `point_mis`: N per optical-depth estimate of the MIS weights (default 10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mis_samples: Option<u32>,
}

impl Default for IntegratorDesc {
    fn default() -> Self {
        IntegratorDesc {
            ty: "transmittance".into(),
            estimator: "ratio_tracking".into(),
            background: [1.0; 3],
            samples: None,
            mode: None,
            step: None,
            jitter: None,
            mult: None,
            doubled: None,
            clip: None,
            distance_sampler: None,
            max_depth: None,
            rr_depth: None,
            preset: None,
            strategy: None,
            mis_samples: None,
        }
    }
}

impl IntegratorDesc {
    pub fn estimator_options(&self) -> fogbank_estimators::EstimatorOptions {
        fogbank_estimators::EstimatorOptions {
            samples: self.samples,
            mode: self.mode.clone(),
            step: self.step,
            jitter: self.jitter.clone(),
            mult: self.mult,
            doubled: self.doubled,
            clip: self.clip,
        }
    }
}

/// | key | default | meaning |
/// |---|---|---|
/// | `spp` | 16 | samples per pixel |
/// | `seed` | 0 | scene seed; the image is a function of scene, seed and spp |
/// | `pixel_jitter` | true | jitter primary rays within pixels (false: pixel centres) |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct RenderDesc {
    pub spp: u32,
    pub seed: u32,
    /// Jitter primary rays within the pixel (antialiasing); `false` sends
    /// them through pixel centres, so per-pixel statistics compare against
    /// a single exact value (`fogbank stats` does this).
    pub pixel_jitter: bool,
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            spp: 16,
            seed: 0,
            pixel_jitter: true,
        }
    }
}

/// The built-in default scene: a procedural cumulus under a sky-like
/// environment, seen through the transmittance integrator.
pub const DEFAULT_SCENE: &str = r#"
[camera]
from = [0.0, 0.05, 2.2]
to = [0.0, -0.05, 0.0]
fov = 38.0
width = 640
height = 480

[[media]]
density = { procedural = "cloud", resolution = 160, seed = 7 }
sigma_t_scale = 8.0
albedo = [0.95, 0.95, 0.95]
phase = { type = "hg", g = 0.6 }
filter = "stochastic_trilinear"

[[lights]]
type = "constant"
radiance = [0.55, 0.7, 1.0]

[[lights]]
type = "directional"
direction = [-0.4, -0.8, -0.3]
irradiance = [3.0, 2.9, 2.7]

[integrator]
type = "transmittance"
estimator = "ratio_tracking"

[render]
spp = 16
seed = 0
"#;

/// Errors of scene parsing and construction, each naming the key or file.
#[derive(Debug)]
pub struct SceneError(pub String);

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SceneError {}

/// Parses the value of a `--set` as TOML (`40`, `"x"`, `[1, 2, 3]`, `true`),
/// falling back to a bare string so `--set integrator.estimator=track_length`
/// needs no quotes.
pub fn parse_value(text: &str) -> toml::Value {
    match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(mut t) => t
            .remove("v")
            .unwrap_or_else(|| toml::Value::String(text.into())),
        Err(_) => toml::Value::String(text.into()),
    }
}

/// Sets `path` (dotted; numbers index arrays) in `doc` to `value`. Missing
/// tables are created; an index past an array's end is an error. Unknown keys
/// are caught afterwards, when the document is deserialised.
pub fn apply_override(
    doc: &mut toml::Table,
    path: &str,
    value: toml::Value,
) -> Result<(), SceneError> {
    let mut root = toml::Value::Table(std::mem::take(doc));
    let result = set_path(&mut root, path, value);
    if let toml::Value::Table(t) = root {
        *doc = t;
    }
    result
}

fn set_path(root: &mut toml::Value, path: &str, value: toml::Value) -> Result<(), SceneError> {
    let parts: Vec<&str> = path.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(SceneError(format!("--set {path}: empty key segment")));
    }
    let (last, parents) = parts.split_last().expect("split yields at least one part");
    let mut node = root;
    for (i, part) in parents.iter().enumerate() {
        let so_far = parts[..=i].join(".");
        node = match node {
            toml::Value::Table(t) => t
                .entry(part.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
            toml::Value::Array(a) => {
                let len = a.len();
                let idx: usize = part.parse().map_err(|_| {
                    SceneError(format!(
                        "--set {path}: `{so_far}` indexes a list, expected a number"
                    ))
                })?;
                a.get_mut(idx).ok_or_else(|| {
                    SceneError(format!(
                        "--set {path}: `{so_far}` is out of range (the list has {len} entries)"
                    ))
                })?
            }
            _ => {
                return Err(SceneError(format!(
                    "--set {path}: `{}` is not a table",
                    parts[..i].join(".")
                )))
            }
        };
    }
    match node {
        toml::Value::Table(t) => {
            t.insert(last.to_string(), value);
            Ok(())
        }
        toml::Value::Array(a) => {
            let len = a.len();
            let idx: usize = last.parse().map_err(|_| {
                SceneError(format!(
                    "--set {path}: `{last}` indexes a list, expected a number"
                ))
            })?;
            let slot = a.get_mut(idx).ok_or_else(|| {
                SceneError(format!(
                    "--set {path}: index {idx} is out of range (the list has {len} entries)"
                ))
            })?;
            *slot = value;
            Ok(())
        }
        _ => Err(SceneError(format!(
            "--set {path}: `{}` is not a table",
            parents.join(".")
        ))),
    }
}

//! Scene construction: from a [`SceneDesc`] to media, lights and camera ready
//! to render. Relative paths resolve against the scene file's folder.

use crate::camera::Camera;
use crate::desc::LightDesc;
use crate::desc::{
    apply_override, parse_value, DensityDesc, MediumDesc, ScaleDesc, SceneDesc, SceneError,
    TransformDesc, DEFAULT_SCENE,
};
use crate::integrators::direct::Direct;
use crate::integrators::media::DistanceSampler;
use crate::integrators::volpath::VolPath;
use crate::lights::sample::LightSampler;
use fogbank_estimators::Estimator;
use fogbank_math::{DAffine3, DVec3, Vec3};
use fogbank_volume::loaders::{raw, vdb, vdb_grid, vol};
use fogbank_volume::{
    medium::unit_box_transform, procedural, AnalyticField, AnalyticKind, BrickGrid, DensityData,
    Filter, Medium, Precision,
};
use glam::DQuat;
use std::path::{Path, PathBuf};

/// A medium of the scene: its extinction plus the scattering properties the
/// later integrators use.
#[derive(Clone, Debug)]
pub struct SceneMedium {
    pub medium: Medium,
    /// Constant albedo, or the tint of `albedo_grid`.
    pub albedo: [f32; 3],
    pub albedo_grid: Option<crate::field::Field>,
    pub emission: Option<crate::emission::Emission>,
    pub phase_g: f32,
    /// What the density came from, for `--stats` and messages.
    pub source: String,
}

impl SceneMedium {
    /// Single-scattering albedo σ_s/σ_t at world point `p`, in [0, 1].
    #[inline]
    pub fn albedo_at(&self, p: Vec3) -> Vec3 {
        let a = Vec3::from(self.albedo);
        match &self.albedo_grid {
            Some(g) => (a * g.eval(p)).clamp(Vec3::ZERO, Vec3::ONE),
            None => a,
        }
    }

    /// Radiance emitted at a real collision at `p` with albedo `albedo`:
    /// (σ_a/σ_t) L_e, so that free-flight sampling (density σ_t T) gives
    /// ∫ T σ_a L_e dt in expectation.
    #[inline]
    pub fn emitted(&self, p: Vec3, albedo: Vec3) -> Vec3 {
        match &self.emission {
            Some(e) => (Vec3::ONE - albedo) * e.radiance(p),
            None => Vec3::ZERO,
        }
    }
}

#[derive(Clone, Debug)]
pub enum Light {
    Constant {
        radiance: Vec3,
    },
    Envmap(std::sync::Arc<crate::lights::envmap::Envmap>),
    Point {
        position: Vec3,
        intensity: Vec3,
    },
    Directional {
        direction: Vec3,
        irradiance: Vec3,
    },
    /// Cosines of the falloff start and of the cone edge.
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cos_falloff_start: f32,
        cos_total: f32,
    },
}

#[derive(Clone, Debug)]
pub enum IntegratorKind {
    Transmittance {
        estimator: Estimator,
        background: Vec3,
    },
    Direct(Direct),
    VolPath(VolPath),
    PointMis(crate::integrators::point_mis::PointMis),
}

impl IntegratorKind {
    pub fn name(&self) -> &'static str {
        match self {
            IntegratorKind::Transmittance { .. } => "transmittance",
            IntegratorKind::Direct(_) => "direct",
            IntegratorKind::VolPath(_) => "volpath",
            IntegratorKind::PointMis(_) => "point_mis",
        }
    }
    /// The transmittance estimator (for `volpath`: the NEE estimator).
    pub fn estimator(&self) -> Estimator {
        match self {
            IntegratorKind::Transmittance { estimator, .. } => *estimator,
            IntegratorKind::Direct(d) => d.nee,
            IntegratorKind::VolPath(v) => v.nee,
            IntegratorKind::PointMis(p) => p.nee,
        }
    }
    pub fn estimator_name(&self) -> &'static str {
        self.estimator().name()
    }
    /// The same integrator with its transmittance estimator replaced.
    pub fn with_estimator(&self, e: Estimator) -> IntegratorKind {
        match self {
            IntegratorKind::Transmittance { background, .. } => IntegratorKind::Transmittance {
                estimator: e,
                background: *background,
            },
            IntegratorKind::Direct(d) => IntegratorKind::Direct(Direct {
                nee: e,
                ..d.clone()
            }),
            IntegratorKind::VolPath(v) => IntegratorKind::VolPath(VolPath {
                nee: e,
                ..v.clone()
            }),
            IntegratorKind::PointMis(p) => {
                IntegratorKind::PointMis(crate::integrators::point_mis::PointMis {
                    nee: e,
                    ..p.clone()
                })
            }
        }
    }
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub desc: SceneDesc,
    pub camera: Camera,
    pub media: Vec<SceneMedium>,
    pub lights: Vec<Light>,
    pub integrator: IntegratorKind,
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
    for o in overrides {
        let (key, value) = o
            .split_once('=')
            .ok_or_else(|| SceneError(format!("--set {o}: expected KEY=VALUE")))?;
        apply_override(&mut doc, key.trim(), parse_value(value.trim()))?;
    }
    // Round-trip through text so error messages carry toml's key paths.
    let text = toml::to_string(&doc).map_err(|e| SceneError(format!("{origin}: {e}")))?;
    toml::from_str(&text).map_err(|e| SceneError(format!("{origin} (after --set overrides): {e}")))
}

impl SceneDesc {
    pub fn default_scene() -> SceneDesc {
        toml::from_str(DEFAULT_SCENE).expect("the built-in scene parses")
    }
}

/// The settings `direct` and `volpath` share: distance sampler, NEE
/// estimator (after the `preset`) and light selection.
fn scattering_settings(
    desc: &SceneDesc,
    media: &[SceneMedium],
    lights: &[Light],
) -> Result<(DistanceSampler, Estimator, LightSampler), SceneError> {
    let d = &desc.integrator;
    let (mut sampler, mut nee) = (d.distance_sampler.clone(), d.estimator.clone());
    match d.preset.as_deref() {
        None => {}
        // Seed 002's baseline: decomposition tracking + residual ratio tracking.
        Some("baseline") => {
            sampler.get_or_insert_with(|| "decomposition_tracking".into());
            nee = "residual_ratio_tracking".into();
        }
        Some(other) => {
            return Err(SceneError(format!(
                "integrator.preset: unknown preset `{other}` (available: baseline)"
            )))
        }
    }
    let sampler = sampler.unwrap_or_else(|| "delta_tracking".into());
    let distance = DistanceSampler::parse(&sampler).ok_or_else(|| {
        SceneError(format!(
            "integrator.distance_sampler: `{sampler}` is not {}",
            DistanceSampler::NAMES
        ))
    })?;
    let nee = Estimator::with_options(&nee, &d.estimator_options())
        .map_err(|e| SceneError(format!("integrator.estimator: {e}")))?;
    // Scene radius for the light-power proxy: the media's world bounds.
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for m in media {
        let b = m.medium.world_bounds();
        lo = lo.min(b.min);
        hi = hi.max(b.max);
    }
    let radius = if lo.x <= hi.x {
        0.5 * (hi - lo).length()
    } else {
        1.0
    };
    Ok((distance, nee, LightSampler::new(lights, radius)))
}

fn volpath_settings(
    desc: &SceneDesc,
    media: &[SceneMedium],
    lights: &[Light],
) -> Result<VolPath, SceneError> {
    let (distance, nee, lights) = scattering_settings(desc, media, lights)?;
    let d = &desc.integrator;
    let max_depth = d.max_depth.unwrap_or(64);
    if max_depth == 0 || max_depth > 100_000 {
        return Err(SceneError(format!(
            "integrator.max_depth: {max_depth} is outside 1..=100000"
        )));
    }
    Ok(VolPath {
        distance,
        nee,
        max_depth,
        rr_depth: d.rr_depth.unwrap_or(3),
        lights,
    })
}

/// Loads a scene file (or the built-in scene when `path` is `None`).
pub fn load_scene(path: Option<&Path>, overrides: &[String]) -> Result<Scene, SceneError> {
    let (text, origin, base) = match path {
        Some(p) => (
            std::fs::read_to_string(p).map_err(|e| SceneError(format!("{}: {e}", p.display())))?,
            p.display().to_string(),
            p.parent().map(Path::to_path_buf).unwrap_or_default(),
        ),
        None => (
            DEFAULT_SCENE.to_string(),
            "built-in scene".to_string(),
            PathBuf::from("."),
        ),
    };
    let desc = parse_scene(&text, &origin, overrides)?;
    Scene::build(desc, &base)
}

fn transform(t: &TransformDesc) -> DAffine3 {
    let s = match &t.scale {
        None => DVec3::ONE,
        Some(ScaleDesc::Uniform(s)) => DVec3::splat(*s as f64),
        Some(ScaleDesc::PerAxis(s)) => DVec3::from(s.map(f64::from)),
    };
    let r = match t.rotate {
        Some([x, y, z, deg]) => {
            let axis = DVec3::new(x as f64, y as f64, z as f64);
            if axis.length() > 0.0 {
                DQuat::from_axis_angle(axis.normalize(), (deg as f64).to_radians())
            } else {
                DQuat::IDENTITY
            }
        }
        None => DQuat::IDENTITY,
    };
    let tr = DVec3::from(t.translate.unwrap_or([0.0; 3]).map(f64::from));
    DAffine3::from_scale_rotation_translation(s, r, tr)
}

fn analytic_kind(name: &str, d: &DensityDesc, key: &str) -> Result<AnalyticKind, SceneError> {
    Ok(match name {
        "empty" => AnalyticKind::Empty,
        "constant" => AnalyticKind::Constant { value: d.value.unwrap_or(1.0) },
        "ramp" => AnalyticKind::Ramp { base: d.value.unwrap_or(0.1), gradient: d.gradient.unwrap_or([1.0, 0.0, 0.0]) },
        "sinusoid" => AnalyticKind::Sinusoid {
            mean: d.value.unwrap_or(1.0),
            amplitude: d.amplitude.unwrap_or(0.9),
            frequency: d.frequency.unwrap_or([2.0, 1.0, 3.0]),
            phase: d.phase.unwrap_or(0.0),
        },
        "slabs" => AnalyticKind::Slabs {
            value: d.value.unwrap_or(1.0),
            count: d.count.unwrap_or(4),
            width: d.width.unwrap_or(0.02),
            axis: d.axis.unwrap_or(0),
        },
        "sphere" => AnalyticKind::Sphere {
            value: d.value.unwrap_or(1.0),
            radius: d.radius.unwrap_or(0.5),
        },
        other => {
            return Err(SceneError(format!(
                "{key}.procedural: unknown procedural medium `{other}` (cloud, constant, ramp, sinusoid, slabs, sphere, empty)"
            )))
        }
    })
}

pub(crate) fn density(
    d: &DensityDesc,
    key: &str,
    base: &Path,
    precision: Precision,
) -> Result<(DensityData, DAffine3, String), SceneError> {
    let sources = [
        d.vdb.is_some(),
        d.vol.is_some(),
        d.raw.is_some(),
        d.procedural.is_some(),
    ];
    if sources.iter().filter(|&&s| s).count() != 1 {
        return Err(SceneError(format!(
            "{key}: give exactly one of `vdb`, `vol`, `raw`, `procedural`"
        )));
    }
    let err = |e: fogbank_volume::VolumeError| SceneError(format!("{key}: {e}"));
    if let Some(f) = &d.vdb {
        let path = base.join(f);
        let g = vdb::read_grid(&path, d.grid.as_deref()).map_err(err)?;
        let (mut grid, xf) = vdb_grid::to_brick_grid(&g).map_err(err)?;
        let mode = d.level_set.as_deref().unwrap_or("fog");
        if vdb_grid::is_level_set(&g) {
            match mode {
                "fog" => grid = vdb_grid::level_set_to_fog(&grid, g.background),
                "raw" => grid = grid.map_values(|v| v.max(0.0)),
                other => {
                    return Err(SceneError(format!(
                        "{key}.level_set: `{other}` is not `fog` or `raw`"
                    )))
                }
            }
        } else {
            grid = grid.map_values(|v| v.max(0.0));
        }
        return Ok((
            DensityData::from_f32(grid, precision),
            xf,
            format!("{} ({})", path.display(), g.name),
        ));
    }
    if let Some(f) = &d.vol {
        let path = base.join(f);
        let v = vol::read_vol(&path).map_err(err)?;
        let grid = v
            .channel_grid(d.channel.unwrap_or(0))
            .map_err(err)?
            .map_values(|x| x.max(0.0));
        return Ok((
            DensityData::from_f32(grid, precision),
            v.index_to_world(),
            path.display().to_string(),
        ));
    }
    if let Some(f) = &d.raw {
        let path = base.join(f);
        let ty = match &d.ty {
            Some(t) => Some(raw::RawType::parse(t).ok_or_else(|| {
                SceneError(format!(
                    "{key}.type: unknown raw type `{t}` (u8, u16, i16, f32, f64)"
                ))
            })?),
            None => None,
        };
        let grid = raw::read_raw(&path, d.dims, ty).map_err(err)?;
        let xf = unit_box_transform(grid.dims());
        return Ok((
            DensityData::from_f32(grid, precision),
            xf,
            path.display().to_string(),
        ));
    }
    let name = d.procedural.as_deref().unwrap_or_default();
    let res = d.resolution.unwrap_or(128);
    if name == "cloud" {
        let grid: BrickGrid<f32> = procedural::cloud_grid(res, d.seed.unwrap_or(7)).map_err(err)?;
        return Ok((
            DensityData::from_f32(grid, precision),
            unit_box_transform([res; 3]),
            format!("procedural cloud {res}³"),
        ));
    }
    let field = AnalyticField::new(analytic_kind(name, d, key)?, res).map_err(err)?;
    Ok((
        DensityData::Analytic(field),
        unit_box_transform([res; 3]),
        format!("analytic {name}"),
    ))
}

fn build_medium(m: &MediumDesc, i: usize, base: &Path) -> Result<SceneMedium, SceneError> {
    let key = format!("media.{i}");
    let filter = Filter::parse(&m.filter).ok_or_else(|| {
        SceneError(format!(
            "{key}.filter: `{}` is not nearest, trilinear or stochastic_trilinear",
            m.filter
        ))
    })?;
    let precision = match m.precision.as_str() {
        "f16" => Precision::F16,
        "f32" => Precision::F32,
        other => {
            return Err(SceneError(format!(
                "{key}.precision: `{other}` is not f16 or f32"
            )))
        }
    };
    if m.supervoxel == 0 || m.supervoxel > 256 {
        return Err(SceneError(format!(
            "{key}.supervoxel: {} is outside 1..=256",
            m.supervoxel
        )));
    }
    if !(m.sigma_t_scale >= 0.0 && m.sigma_t_scale.is_finite()) {
        return Err(SceneError(format!(
            "{key}.sigma_t_scale: must be a finite value ≥ 0"
        )));
    }
    if m.phase.ty != "hg" && m.phase.ty != "isotropic" {
        return Err(SceneError(format!(
            "{key}.phase.type: `{}` is not hg or isotropic",
            m.phase.ty
        )));
    }
    if !(m.phase.g > -1.0 && m.phase.g < 1.0) {
        return Err(SceneError(format!(
            "{key}.phase.g: {} is outside (−1, 1)",
            m.phase.g
        )));
    }
    let (data, file_xf, source) = density(&m.density, &format!("{key}.density"), base, precision)?;
    let placement = transform(&m.to_world);
    let xf = placement * file_xf;
    if xf.matrix3.determinant().abs() < 1e-30 {
        return Err(SceneError(format!("{key}.to_world: transform is singular")));
    }
    if !m.albedo.iter().all(|a| (0.0..=1.0).contains(a)) {
        return Err(SceneError(format!(
            "{key}.albedo: each channel must be in [0, 1], got {:?}",
            m.albedo
        )));
    }
    let albedo_grid = m
        .albedo_grid
        .as_ref()
        .map(|g| crate::field::Field::load(g, &format!("{key}.albedo_grid"), base, placement))
        .transpose()?;
    let emission = m
        .emission
        .as_ref()
        .map(|e| crate::emission::Emission::build(e, &format!("{key}.emission"), base, placement))
        .transpose()?;
    Ok(SceneMedium {
        medium: Medium::new(data, m.sigma_t_scale, filter, xf, m.supervoxel),
        albedo: m.albedo,
        albedo_grid,
        emission,
        phase_g: if m.phase.ty == "isotropic" {
            0.0
        } else {
            m.phase.g
        },
        source,
    })
}

impl Scene {
    pub fn build(desc: SceneDesc, base: &Path) -> Result<Scene, SceneError> {
        let c = &desc.camera;
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
        let camera = Camera::new(
            Vec3::from(c.from),
            Vec3::from(c.to),
            Vec3::from(c.up),
            c.fov,
            fov_x,
            c.width,
            c.height,
        )
        .ok_or_else(|| {
            SceneError(
                "camera: `from`, `to` and `up` must span a frame (from ≠ to, up not parallel)"
                    .into(),
            )
        })?;
        let media = desc
            .media
            .iter()
            .enumerate()
            .map(|(i, m)| build_medium(m, i, base))
            .collect::<Result<Vec<_>, _>>()?;
        let lights = desc
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                Ok(match l {
                    LightDesc::Constant { radiance } => Light::Constant {
                        radiance: Vec3::from(*radiance),
                    },
                    LightDesc::Envmap {
                        file,
                        scale,
                        rotate,
                    } => {
                        let path = base.join(file);
                        let rotation = match rotate {
                            Some([x, y, z, deg]) => glam::Mat3::from_axis_angle(
                                Vec3::new(*x, *y, *z).try_normalize().ok_or_else(|| {
                                    SceneError(format!("lights.{i}.rotate: zero axis"))
                                })?,
                                deg.to_radians(),
                            ),
                            None => glam::Mat3::IDENTITY,
                        };
                        let env = crate::lights::envmap::Envmap::load(&path, *scale, rotation)
                            .map_err(|e| SceneError(format!("lights.{i}: {e}")))?;
                        Light::Envmap(std::sync::Arc::new(env))
                    }
                    LightDesc::Point {
                        position,
                        intensity,
                    } => Light::Point {
                        position: Vec3::from(*position),
                        intensity: Vec3::from(*intensity),
                    },
                    LightDesc::Directional {
                        direction,
                        irradiance,
                    } => Light::Directional {
                        direction: Vec3::from(*direction).try_normalize().ok_or_else(|| {
                            SceneError(format!("lights.{i}.direction: zero vector"))
                        })?,
                        irradiance: Vec3::from(*irradiance),
                    },
                    LightDesc::Spot { position, direction, intensity, cone_angle, falloff_start } => {
                        if !(*cone_angle > 0.0 && *cone_angle <= 180.0 && *falloff_start >= 0.0 && falloff_start <= cone_angle) {
                            return Err(SceneError(format!(
                                "lights.{i}: need 0 ≤ falloff_start ≤ cone_angle ≤ 180 degrees, cone_angle > 0"
                            )));
                        }
                        Light::Spot {
                            position: Vec3::from(*position),
                            direction: Vec3::from(*direction)
                                .try_normalize()
                                .ok_or_else(|| SceneError(format!("lights.{i}.direction: zero vector")))?,
                            intensity: Vec3::from(*intensity),
                            cos_falloff_start: falloff_start.to_radians().cos(),
                            cos_total: cone_angle.to_radians().cos(),
                        }
                    }
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;
        if desc.integrator.ty != "point_mis" {
            if let Some(key) = [
                ("strategy", desc.integrator.strategy.is_some()),
                ("mis_samples", desc.integrator.mis_samples.is_some()),
            ]
            .iter()
            .find_map(|(k, set)| set.then_some(k))
            {
                return Err(SceneError(format!(
                    "integrator.{key}: only used by integrator.type = \"point_mis\""
                )));
            }
        }
        let integrator = match desc.integrator.ty.as_str() {
            "transmittance" => {
                let estimator = Estimator::with_options(
                    &desc.integrator.estimator,
                    &desc.integrator.estimator_options(),
                )
                .map_err(|e| SceneError(format!("integrator.estimator: {e}")))?;
                IntegratorKind::Transmittance {
                    estimator,
                    background: Vec3::from(desc.integrator.background),
                }
            }
            "direct" => {
                // `max_depth` and `rr_depth` are volpath's; direct ignores them so
                // `--set integrator.type=direct` works on any volpath scene.
                let (distance, nee, lights) = scattering_settings(&desc, &media, &lights)?;
                IntegratorKind::Direct(Direct {
                    distance,
                    nee,
                    lights,
                })
            }
            "volpath" => IntegratorKind::VolPath(volpath_settings(&desc, &media, &lights)?),
            "point_mis" => IntegratorKind::PointMis(crate::integrators::point_mis::settings(
                &desc, &media, &lights,
            )?),
            other => {
                return Err(SceneError(format!(
                "integrator.type: unknown integrator `{other}` (available: transmittance, direct, volpath, point_mis)"
            )))
            }
        };
        Ok(Scene {
            desc,
            camera,
            media,
            lights,
            integrator,
        })
    }
}

//! A medium of the scene: its extinction grid and placement plus the
//! scattering properties (albedo, emission, phase) integrators use.

use super::chroma::{rgb_density, Chroma};
use super::classified::classify;
use super::emission::{Emission, EmissionDesc};
use super::field::{field_data, Field, FieldData, FieldDesc};
use super::importance::{Importance, ImportanceInputs, ImportancePreDesc, ImportanceRuleDesc};
use super::phase::{HenyeyGreenstein, PhaseDesc};
use super::transfer::{TransferDesc, TransferLookup};
use super::velocity::{Velocity, VelocityDesc};
use crate::error::SceneError;
use fogbank_math::{DAffine3, DVec3, Vec3};
use fogbank_volume::{DensityData, Filter, Medium, Precision};
use glam::DQuat;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// | key | default | meaning |
/// |---|---|---|
/// | `density` | — | data source, see [`FieldDesc`] |
/// | `sigma_t_scale` | 1 | σ_t = scale · density (per world unit); `[r, g, b]` for chromatic extinction, see [`Chroma`] (volpath, direct and transmittance, CPU and GPU) |
/// | `density_rgb` | false | the `density` is a 3-channel `.vol` (Mitsuba's RGB `gridvolume`) or in-memory `array`: σ_t of channel c = `sigma_t_scale`_c · channel c (chromatic; `trilinear` filter, f32) |
/// | `albedo` | (0.8, 0.8, 0.8); (1, 1, 1) with a `transfer` | single-scattering albedo σ_s/σ_t, each channel in [0, 1] (with a `transfer`, a tint of its colours); pbrt-v4's default is 0.5 and Mitsuba 3's 0.75, which their readers write (`docs/results/defaults.md`) |
/// | `importance` | none | ordered rules mapping points to importance in [0, 1] for `visopt` (Lerzer and Dachsbacher 2025 §4.2), see [`ImportanceRuleDesc`] |
/// | `importance_pre` | none (post-interpolative) | classify the importance per voxel instead, see [`ImportancePreDesc`] (Lerzer and Dachsbacher 2025 Figs. 3, 11) |
/// | `transfer` | none | a transfer function classifying the density's values into extinction, albedo and emission, see [`TransferDesc`] |
/// | `albedo_grid` | none | a grid (same keys as `density`, placed like it) multiplying `albedo`; a 3-channel `.vol` without `channel` gives RGB; values clamp to [0, 1] |
/// | `emission` | none | volumetric emission, see [`EmissionDesc`] |
/// | `phase` | `{ type = "hg", g = 0 }` | phase function |
/// | `to_world` | identity | placement after the file's own transform |
/// | `filter` | `"stochastic_trilinear"`; `"trilinear"` with a post-interpolative `transfer` | `nearest`, `trilinear`, `stochastic_trilinear` (not with a post-interpolative `transfer`: classifying jittered nearest lookups is pre-interpolative in expectation). pbrt-v4 and Mitsuba 3 filter trilinearly; the stochastic filter has the trilinear medium's expectation under every null-collision estimator (each is linear in σ_t at a lookup) for one voxel fetch instead of eight |
/// | `supervoxel` | 16 | super-voxel edge in voxels |
/// | `precision` | `"f16"` | voxel storage, `f16` (half the memory; rounding ≤ 2⁻¹¹ of a value; a grid with values beyond ±65504 is refused) or `f32` (the file's values; pbrt-v4's and Mitsuba 3's) |
/// | `velocity` | none (a plume's own) | motion for temporal reuse, see [`VelocityDesc`] |
/// | `instances` | none | placements (applied after `to_world`) of copies sharing the grid (Hansen 2025 Fig. 4.10); with it the medium appears once per entry |
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MediumDesc {
    pub density: FieldDesc,
    #[serde(default = "one")]
    pub sigma_t_scale: SigmaTScale,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub density_rgb: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo: Option<[f32; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transfer: Option<TransferDesc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub importance: Vec<ImportanceRuleDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub importance_pre: Option<ImportancePreDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo_grid: Option<FieldDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emission: Option<EmissionDesc>,
    #[serde(default)]
    pub phase: PhaseDesc,
    #[serde(default)]
    pub to_world: TransformDesc,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<String>,
    #[serde(default = "default_supervoxel")]
    pub supervoxel: u32,
    #[serde(default = "default_precision")]
    pub precision: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<VelocityDesc>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub instances: Vec<TransformDesc>,
}

fn one() -> SigmaTScale {
    SigmaTScale::Grey(1.0)
}

/// `sigma_t_scale`: one scale for every channel, or one per RGB channel.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum SigmaTScale {
    Grey(f32),
    Rgb([f32; 3]),
}

impl SigmaTScale {
    pub fn channels(self) -> [f32; 3] {
        match self {
            SigmaTScale::Grey(s) => [s; 3],
            SigmaTScale::Rgb(c) => c,
        }
    }

    /// The largest channel's scale (the one free flights track).
    pub fn max(self) -> f32 {
        let c = self.channels();
        c[0].max(c[1]).max(c[2])
    }

    /// The same colour with its largest channel at `max`.
    pub fn with_max(self, max: f32) -> SigmaTScale {
        match self {
            SigmaTScale::Grey(_) => SigmaTScale::Grey(max),
            SigmaTScale::Rgb(c) => {
                let m = self.max();
                SigmaTScale::Rgb(c.map(|s| if m > 0.0 { s / m * max } else { max }))
            }
        }
    }
}
fn default_supervoxel() -> u32 {
    16
}
fn default_precision() -> String {
    "f16".into()
}

/// Applied as translate · rotate · scale · matrix.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TransformDesc {
    pub translate: Option<[f32; 3]>,
    /// Uniform (`scale = 2`) or per axis (`scale = [1, 2, 1]`).
    pub scale: Option<ScaleDesc>,
    /// Axis and angle in degrees: `[x, y, z, degrees]`.
    pub rotate: Option<[f32; 4]>,
    /// An affine 4×4 matrix, rows top to bottom (the last row `[0, 0, 0, 1]`),
    /// as Mitsuba's `<matrix>` and what the XML reader writes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[[f64; 4]; 4]>,
}

impl TransformDesc {
    /// A `matrix` must be finite and affine (last row 0 0 0 1).
    pub fn check(&self, key: &str) -> Result<(), SceneError> {
        if let Some(m) = &self.matrix {
            if m.iter().flatten().any(|x| !x.is_finite()) || m[3] != [0.0, 0.0, 0.0, 1.0] {
                return Err(SceneError(format!(
                    "{key}.matrix: needs finite values and the last row [0, 0, 0, 1]"
                )));
            }
        }
        Ok(())
    }
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(f32),
    PerAxis([f32; 3]),
}

/// A medium of the scene: its extinction plus the scattering properties the
/// later integrators use.
#[derive(Clone, Debug)]
pub struct SceneMedium {
    /// Extinction of the largest channel (all channels when achromatic).
    pub medium: Medium,
    /// Per-channel extinction when the channels differ.
    pub chroma: Option<Chroma>,
    /// Constant albedo, or the tint of `albedo_grid`.
    pub albedo: [f32; 3],
    pub albedo_grid: Option<Field>,
    pub emission: Option<Emission>,
    /// A post-interpolative transfer function's colour and emission,
    /// evaluated at the interpolated scalar.
    pub transfer: Option<TransferLookup>,
    /// Where the medium matters for visibility optimisation (Lerzer and Dachsbacher 2025).
    pub importance: Importance,
    /// The phase function (pbrt-v4's and Mitsuba 3's media hold one too;
    /// Henyey–Greenstein is the only model, g = 0 isotropic).
    pub phase: HenyeyGreenstein,
    /// What the density came from, for `--stats` and messages.
    pub source: String,
    /// How the medium's matter moves (None: it is still).
    pub velocity: Option<Velocity>,
    /// The `[[media]]` entry this medium comes from (instances share one).
    pub entry: usize,
}

impl SceneMedium {
    /// Single-scattering albedo σ_s/σ_t at world point `p`, in [0, 1].
    #[inline]
    pub fn albedo_at(&self, p: Vec3) -> Vec3 {
        let a = Vec3::from(self.albedo);
        if let Some(t) = &self.transfer {
            return (a * t.color(self.scalar_at(p))).clamp(Vec3::ZERO, Vec3::ONE);
        }
        match &self.albedo_grid {
            Some(g) => (a * g.eval(p)).clamp(Vec3::ZERO, Vec3::ONE),
            None => a,
        }
    }

    /// σ_t at world point `p` from the trilinear interpolant (classified
    /// after interpolation), whatever the medium's filter: the smooth field
    /// that gradients and importance criteria read.
    #[inline]
    pub fn sigma_t_smooth(&self, p: Vec3) -> f32 {
        let q = self
            .medium
            .world_to_index
            .transform_point3(p.as_dvec3())
            .as_vec3();
        self.medium.sigma_t_smooth(q)
    }

    /// ∇σ_t at world point `p` (Lerzer and Dachsbacher 2025 §3: the gradient of the classified
    /// extinction), by central differences of one voxel in index space,
    /// turned into world units with the inverse-transpose Jacobian.
    pub fn gradient_sigma_t(&self, p: Vec3) -> Vec3 {
        let w2i = self.medium.world_to_index;
        let q = w2i.transform_point3(p.as_dvec3()).as_vec3();
        let at = |o: Vec3| {
            let s = self.medium.scalar_trilinear(q + o);
            self.medium.sigma_t_scale * self.medium.opacity.as_ref().map_or(s, |a| a.eval(s)[0])
        };
        let g_index = Vec3::new(
            at(Vec3::X) - at(-Vec3::X),
            at(Vec3::Y) - at(-Vec3::Y),
            at(Vec3::Z) - at(-Vec3::Z),
        ) * 0.5;
        (w2i.matrix3.transpose() * g_index.as_dvec3()).as_vec3()
    }

    /// The density's value (before classification) at world point `p`,
    /// trilinearly interpolated; 0 outside the medium's box.
    #[inline]
    pub fn scalar_at(&self, p: Vec3) -> f32 {
        let q = self
            .medium
            .world_to_index
            .transform_point3(p.as_dvec3())
            .as_vec3();
        self.medium.scalar_trilinear(q)
    }

    /// Radiance emitted at a real collision at `p` with albedo `albedo`:
    /// (σ_a/σ_t) L_e, so that free-flight sampling (density σ_t T) gives
    /// ∫ T σ_a L_e dt in expectation.
    #[inline]
    pub fn emitted(&self, p: Vec3, albedo: Vec3) -> Vec3 {
        if let Some(e) = self
            .transfer
            .as_ref()
            .and_then(|t| t.emission(self.scalar_at(p)))
        {
            return (Vec3::ONE - albedo) * e;
        }
        match &self.emission {
            Some(e) => (Vec3::ONE - albedo) * e.radiance(p),
            None => Vec3::ZERO,
        }
    }
}

/// Most instances one `[[media]]` entry may have.
pub const MAX_INSTANCES: usize = 1 << 16;

impl MediumDesc {
    /// The media of entry `media.{i}`: itself, or one copy per `instances`
    /// entry, sharing the grid (the copies differ only in placement).
    pub fn build_instances(&self, i: usize, base: &Path) -> Result<Vec<SceneMedium>, SceneError> {
        let first = self.build(i, base)?;
        if self.instances.is_empty() {
            return Ok(vec![first]);
        }
        let key = format!("media.{i}.instances");
        if self.instances.len() > MAX_INSTANCES {
            return Err(SceneError(format!(
                "{key}: {} instances, more than the limit of {MAX_INSTANCES}",
                self.instances.len()
            )));
        }
        if self.albedo_grid.is_some() || self.emission.is_some() || self.velocity.is_some() {
            return Err(SceneError(format!(
                "{key}: instances share one density grid only: a medium with albedo_grid, emission or velocity cannot be instanced"
            )));
        }
        self.instances
            .iter()
            .enumerate()
            .map(|(j, t)| {
                let xf = transform(t) * first.medium.index_to_world;
                let det = xf.matrix3.determinant().abs();
                if det.is_nan() || det < 1e-30 {
                    return Err(SceneError(format!("{key}.{j}: transform is singular")));
                }
                let mut m = first.clone();
                m.medium.index_to_world = xf;
                m.medium.world_to_index = xf.inverse();
                Ok(m)
            })
            .collect()
    }

    /// The filter and voxel precision this entry asks for, after checking
    /// them and
    /// the other scalar options (super-voxel size, extinction scale,
    /// phase function) against their ranges.
    fn sampling(&self, key: &str) -> Result<(Filter, Precision), SceneError> {
        let m = self;
        let post = m
            .transfer
            .as_ref()
            .is_some_and(|t| t.mode.as_deref().unwrap_or("post") == "post");
        let filter_name = m.filter.as_deref().unwrap_or(if post || m.density_rgb {
            "trilinear"
        } else {
            "stochastic_trilinear"
        });
        let filter = Filter::parse(filter_name).ok_or_else(|| {
            SceneError(format!(
                "{key}.filter: `{filter_name}` is not nearest, trilinear or stochastic_trilinear"
            ))
        })?;
        if post && filter == Filter::StochasticTrilinear {
            return Err(SceneError(format!(
                "{key}.filter: stochastic_trilinear classifies jittered voxel values, which is \
                 pre-interpolative in expectation; a post-interpolative transfer needs `trilinear` \
                 (or `nearest`)"
            )));
        }
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
        if !m
            .sigma_t_scale
            .channels()
            .iter()
            .all(|s| *s >= 0.0 && s.is_finite())
        {
            return Err(SceneError(format!(
                "{key}.sigma_t_scale: must be finite values ≥ 0"
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
        Ok((filter, precision))
    }

    /// The constant albedo (the tint of `albedo_grid`): 1 under a transfer
    /// function, which gives the colour, else 0.8.
    fn constant_albedo(&self, key: &str) -> Result<[f32; 3], SceneError> {
        let m = self;
        let albedo = m.albedo.unwrap_or(if m.transfer.is_some() {
            [1.0; 3]
        } else {
            [0.8; 3]
        });
        if !albedo.iter().all(|a| (0.0..=1.0).contains(a)) {
            return Err(SceneError(format!(
                "{key}.albedo: each channel must be in [0, 1], got {albedo:?}"
            )));
        }
        Ok(albedo)
    }

    /// The density's voxels (with their file's transform, source and
    /// stored range), and for `density_rgb` the three channels' grids.
    fn density(
        &self,
        key: &str,
        base: &Path,
        filter: Filter,
        precision: Precision,
    ) -> Result<(FieldData, Option<[DensityData; 3]>), SceneError> {
        let m = self;
        let dkey = format!("{key}.density");
        if m.density_rgb {
            if m.transfer.is_some() || filter != Filter::Trilinear {
                return Err(SceneError(format!(
                    "{key}.density_rgb: needs filter = \"trilinear\" and no transfer function"
                )));
            }
            let (f, g) = rgb_density(&m.density, &dkey, base, m.sigma_t_scale.channels())?;
            Ok((f, Some(g)))
        } else {
            Ok((field_data(&m.density, &dkey, base, precision)?, None))
        }
    }

    /// The importance rule of Lerzer and Dachsbacher 2025, reading the density's scalar in
    /// its stored range `units` (normalised to [0, 1]).
    fn importance(
        &self,
        key: &str,
        base: &Path,
        units: Option<(f32, f32)>,
        placement: DAffine3,
    ) -> Result<Importance, SceneError> {
        let m = self;
        let stored = units.map_or((1.0, 0.0), |(lo, hi)| {
            if hi > lo {
                (1.0 / (hi - lo), -lo / (hi - lo))
            } else {
                (1.0, -lo)
            }
        });
        Importance::build(
            &m.importance,
            &format!("{key}.importance"),
            base,
            stored,
            placement,
        )
    }

    /// The medium `media.{i}`, its files resolved against `base`.
    pub fn build(&self, i: usize, base: &Path) -> Result<SceneMedium, SceneError> {
        let m = self;
        let key = format!("media.{i}");
        let (filter, precision) = m.sampling(&key)?;
        let (field, rgb_grids) = m.density(&key, base, filter, precision)?;
        let FieldData {
            data,
            to_world: file_xf,
            source,
            units,
        } = field;
        m.to_world.check(&format!("{key}.to_world"))?;
        let placement = transform(&m.to_world);
        let xf = placement * file_xf;
        if xf.matrix3.determinant().abs() < 1e-30 {
            return Err(SceneError(format!("{key}.to_world: transform is singular")));
        }
        let albedo = m.constant_albedo(&key)?;
        let mut albedo_grid = m
            .albedo_grid
            .as_ref()
            .map(|g| Field::load(g, &format!("{key}.albedo_grid"), base, placement))
            .transpose()?;
        let mut emission = m
            .emission
            .as_ref()
            .map(|e| Emission::build(e, &format!("{key}.emission"), base, placement))
            .transpose()?;
        let (data, opacity, transfer) = match &m.transfer {
            None => (data, None, None),
            Some(t) => {
                let c = classify(t, &key, base, units, data, precision, xf)?;
                let tkey = format!("{key}.transfer");
                if albedo_grid.is_some() || emission.is_some() {
                    return Err(SceneError(format!(
                        "{tkey}: a transfer function gives albedo and emission; drop `albedo_grid` and `emission`"
                    )));
                }
                (albedo_grid, emission) = (c.albedo_grid, c.emission);
                (c.data, c.opacity, c.lookup)
            }
        };
        let velocity = Velocity::build(m.velocity.as_ref(), &m.density, &key, base, placement, xf)?;
        let importance = m.importance(&key, base, units, placement)?;
        let (scale, channels) = (m.sigma_t_scale.max(), m.sigma_t_scale.channels());
        let medium = Medium::classified(data, opacity, scale, filter, xf, m.supervoxel);
        let chroma = match rgb_grids {
            Some(g) => Some(Chroma::from_grids(&medium, g, channels)),
            None => Chroma::new(&medium, channels),
        };
        if chroma.is_some() && (m.velocity.is_some() || !m.instances.is_empty()) {
            return Err(SceneError(format!(
                "{key}.sigma_t_scale: chromatic extinction is one density with a scale per channel; it cannot be combined with velocity or instances"
            )));
        }
        let mut sm = SceneMedium {
            velocity,
            medium,
            chroma,
            albedo,
            albedo_grid,
            emission,
            transfer,
            importance,
            phase: HenyeyGreenstein {
                g: if m.phase.ty == "isotropic" {
                    0.0
                } else {
                    m.phase.g
                },
            },
            source,
            entry: i,
        };
        if let Some(pre) = &m.importance_pre {
            sm.preclassify_importance(pre, &format!("{key}.importance_pre"))?;
        }
        Ok(sm)
    }
}

impl SceneMedium {
    /// Classifies the importance rule over the voxels once (Lerzer and Dachsbacher 2025's
    /// pre-classified importance) instead of per lookup.
    fn preclassify_importance(
        &mut self,
        pre: &ImportancePreDesc,
        pkey: &str,
    ) -> Result<(), SceneError> {
        if matches!(self.medium.data, DensityData::Analytic(_)) {
            return Err(SceneError(format!(
                "{pkey}: analytic media have no voxels to classify"
            )));
        }
        let gradient = self.importance.needs_gradient();
        let inputs = |p: Vec3| ImportanceInputs {
            p,
            sigma_t: self.sigma_t_smooth(p),
            scalar: self.scalar_at(p),
            gradient: if gradient {
                self.gradient_sigma_t(p).length()
            } else {
                0.0
            },
        };
        let (dims, xf) = (self.medium.dims(), self.medium.index_to_world);
        self.importance = self.importance.preclassified(dims, xf, inputs, pre, pkey)?;
        Ok(())
    }
}

pub fn transform(t: &TransformDesc) -> DAffine3 {
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
    let trs = DAffine3::from_scale_rotation_translation(s, r, tr);
    match t.matrix {
        // A projective last row is not an affine map; it is dropped here
        // and refused by the XML reader, which writes this key.
        Some(m) => trs * DAffine3::from_mat4(glam::DMat4::from_cols_array_2d(&m).transpose()),
        None => trs,
    }
}

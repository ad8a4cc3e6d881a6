//! Spatially varying medium properties other than extinction (albedo,
//! emission colour, temperature): a grid placed in the world like the
//! density, looked up with trilinear interpolation at scattering vertices.

use super::arrays;
use crate::error::SceneError;
use fogbank_math::{DAffine3, Vec3};
pub use fogbank_volume::formats::FieldData;
use fogbank_volume::formats::{self, FileSource, VolumeFormat};
use fogbank_volume::loaders::vol;
use fogbank_volume::{
    bunny, explosion, medium::unit_box_transform, plume, procedural, AnalyticField, AnalyticKind,
    BrickGrid, DensityData, Precision,
};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The source of a scalar field (density, albedo, emission, temperature).
/// Exactly one source key: a volume format's (`vdb`, `nvdb`, `vol`,
/// `nifti`, `nrrd`, `raw`: see each file of [`fogbank_volume::formats`] for its
/// further keys), `array` or `procedural`.
///
/// | source | further keys |
/// |---|---|
/// | `vdb = "f.vdb"` | `grid` (default `density`, else the first float grid), `level_set` = `"fog"` (default) or `"raw"` |
/// | `nvdb = "f.nvdb"` | a NanoVDB file (float, double, Fp4/Fp8/Fp16/FpN grids; uncompressed, ZIP or BLOSC); `grid` and `level_set` as for `vdb` |
/// | `vol = "f.vol"` | `channel` (default 0) |
/// | `raw = "f.raw"` | `dims = [x, y, z]`, `type = "u8"/"u16"/"f32"` (or from a `name_XxYxZ_uint8.raw` file name) |
/// | `nifti = "f.nii.gz"` | `channel` (the 3D volume of a 4D file, 0); placed by the sform/qform in RAS millimetres; values rescaled from their range onto [0, 1] |
/// | `nrrd = "f.nrrd"` / `"f.nhdr"` | `channel` (entry of a non-spatial axis, 0); placed by `space directions`/`space origin`, LPS turned to RAS; values rescaled onto [0, 1] |
/// | `array = "array:3"` | `channel` (default 0; a 3-channel array without it is an RGB field); an in-memory array (`fogbank.Grid` from numpy), placed by its own box (see [`super::arrays`]) |
/// | `procedural = "cloud"` | `resolution` (128), `seed` (7) |
/// | `procedural = "explosion"` | `resolution` (128), `seed` (7), `quantity` = `"density"` (default) or `"temperature"` (kelvin, for blackbody emission) |
/// | `procedural = "plume"` | `resolution` (128), `seed` (7), `time` (seconds, 0; an `[animation]` adds frame/fps); rising, swirling smoke with an analytic velocity |
/// | `procedural = "constant"/"ramp"/"sinusoid"/"slabs"/"sphere"/"empty"` | `resolution`, `value`, `gradient`, `amplitude`, `frequency`, `phase`, `count`, `width`, `axis`, `radius` |
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
pub struct FieldDesc {
    /// The file keys (`vdb = "f.vdb"`, …), one per registered volume format
    /// ([`fogbank_volume::formats`]); every other key of the table is refused here.
    #[serde(flatten)]
    pub files: FileKeys,
    pub grid: Option<String>,
    pub level_set: Option<String>,
    pub channel: Option<u32>,
    /// An in-memory array registered by name ([`super::arrays`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub array: Option<String>,
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
    /// `procedural = "explosion"`: `density` (default) or `temperature` (kelvin).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quantity: Option<String>,
    /// `procedural = "plume"`: the time shown, in seconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<f32>,
}

/// The keys of a field's table beside the file keys, for messages.
const FIELD_KEYS: [&str; 20] = [
    "grid",
    "level_set",
    "channel",
    "array",
    "dims",
    "type",
    "procedural",
    "resolution",
    "seed",
    "value",
    "gradient",
    "amplitude",
    "frequency",
    "phase",
    "count",
    "width",
    "axis",
    "radius",
    "quantity",
    "time",
];

/// A field's file keys (`nrrd = "f.nhdr"`), in the table's order: each a
/// registered volume format's ([`formats::by_key`]). A key that is neither
/// one nor a field key is refused, as serde refuses unknown fields.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FileKeys(pub Vec<(&'static str, String)>);

impl FileKeys {
    /// The one file source and its format (the first, if several are given:
    /// the reader refuses that).
    pub fn source(&self) -> Option<(&'static VolumeFormat, &str)> {
        let (key, path) = self.0.first()?;
        Some((formats::by_key(key)?, path.as_str()))
    }

    /// The file of format `key`, if given.
    pub fn path_of(&self, key: &str) -> Option<&String> {
        self.0.iter().find(|(k, _)| *k == key).map(|(_, p)| p)
    }

    /// Sets the file of format `format` (a field with one source).
    pub fn set(&mut self, format: &'static VolumeFormat, path: String) {
        self.0 = vec![(format.key, path)];
    }

    /// Every file name, to rewrite.
    pub fn paths_mut(&mut self) -> impl Iterator<Item = &mut String> {
        self.0.iter_mut().map(|(_, p)| p)
    }
}

impl Serialize for FileKeys {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, p)| (k, p)))
    }
}

impl<'de> Deserialize<'de> for FileKeys {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Keys;
        impl<'de> serde::de::Visitor<'de> for Keys {
            type Value = FileKeys;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a field's keys")
            }
            fn visit_map<M: serde::de::MapAccess<'de>>(
                self,
                mut m: M,
            ) -> Result<FileKeys, M::Error> {
                let mut keys = Vec::new();
                while let Some(k) = m.next_key::<String>()? {
                    match formats::by_key(&k) {
                        Some(f) => keys.push((f.key, m.next_value::<String>()?)),
                        None => return Err(serde::de::Error::unknown_field(&k, expected_keys())),
                    }
                }
                Ok(FileKeys(keys))
            }
        }
        d.deserialize_map(Keys)
    }
}

/// Every key a field's table takes: the formats', then the others.
fn expected_keys() -> &'static [&'static str] {
    static KEYS: std::sync::LazyLock<Vec<&'static str>> = std::sync::LazyLock::new(|| {
        (formats::all().iter().map(|f| f.key))
            .chain(FIELD_KEYS)
            .collect()
    });
    &KEYS
}

#[derive(Clone, Debug)]
pub struct Field {
    /// One channel (a scalar, splatted to RGB) or three (RGB).
    channels: Vec<DensityData>,
    world_to_index: DAffine3,
    dims: [u32; 3],
    pub source: String,
}

impl Field {
    /// Loads the grid `d` of scene key `key`; `to_world` is the medium's
    /// placement, applied after the file's own transform, so property grids
    /// line up with a density grid from the same kind of file.
    pub fn load(
        d: &FieldDesc,
        key: &str,
        base: &Path,
        to_world: DAffine3,
    ) -> Result<Field, SceneError> {
        let (channels, file_xf, source) = match (d.files.path_of("vol"), &d.array) {
            // A 3-channel .vol or array without `channel` is an RGB grid
            // (Mitsuba's convention for albedo).
            (Some(f), None) if d.channel.is_none() => {
                let path = base.join(f);
                let v = vol::read_vol(&path).map_err(|e| SceneError(format!("{key}: {e}")))?;
                let grids = (0..v.channels.min(3)).map(|c| v.channel_grid(c));
                let channels = rgb_or_scalar(v.channels, grids, key)?;
                (channels, v.index_to_world(), path.display().to_string())
            }
            (None, Some(name)) if d.channel.is_none() && d.procedural.is_none() => {
                let a = arrays::get(name, key)?;
                let grids = (0..a.channels().min(3)).map(|c| a.channel_grid(c));
                let channels = rgb_or_scalar(a.channels(), grids, key)?;
                (channels, a.index_to_world(), a.describe())
            }
            _ => {
                let f = field_data(d, key, base, Precision::F32)?;
                (vec![f.data], f.to_world, f.source)
            }
        };
        let xf = to_world * file_xf;
        if xf.matrix3.determinant().abs() < 1e-30 {
            return Err(SceneError(format!("{key}: transform is singular")));
        }
        Ok(Field {
            dims: channels[0].dims(),
            channels,
            world_to_index: xf.inverse(),
            source,
        })
    }

    /// A field of one or three channel grids sharing the index → world map
    /// `index_to_world`.
    pub fn from_channels(
        channels: Vec<DensityData>,
        index_to_world: DAffine3,
        source: String,
    ) -> Result<Field, SceneError> {
        let dims = channels.first().map(|c| c.dims()).unwrap_or([0; 3]);
        if !(channels.len() == 1 || channels.len() == 3)
            || channels.iter().any(|c| c.dims() != dims)
        {
            return Err(SceneError(format!(
                "{source}: a field has one or three channels of equal size"
            )));
        }
        if index_to_world.matrix3.determinant().abs() < 1e-30 {
            return Err(SceneError(format!("{source}: transform is singular")));
        }
        Ok(Field {
            dims,
            channels,
            world_to_index: index_to_world.inverse(),
            source,
        })
    }

    /// The channel grids and the world → index map, for GPU upload.
    pub fn parts(&self) -> (&[DensityData], DAffine3) {
        (&self.channels, self.world_to_index)
    }

    pub fn channel_count(&self) -> usize {
        self.channels.len()
    }

    /// The value of the voxel containing world point `p` (no
    /// interpolation); zero outside the grid's box.
    pub fn eval_nearest(&self, p: Vec3) -> Vec3 {
        self.lookup(p, true)
    }

    /// Trilinearly interpolated value at world point `p`; zero outside the
    /// grid's box, like the density.
    pub fn eval(&self, p: Vec3) -> Vec3 {
        self.lookup(p, false)
    }

    fn lookup(&self, p: Vec3, nearest: bool) -> Vec3 {
        let q = self.world_to_index.transform_point3(p.as_dvec3()).as_vec3();
        let d = Vec3::new(
            self.dims[0] as f32,
            self.dims[1] as f32,
            self.dims[2] as f32,
        );
        if !(q.cmpge(Vec3::ZERO).all() && q.cmple(d).all()) {
            return Vec3::ZERO;
        }
        let one = |c: &DensityData| match (c, nearest) {
            (DensityData::F16(g), false) => g.trilinear(q),
            (DensityData::F32(g), false) => g.trilinear(q),
            (DensityData::F16(g), true) => g.nearest(q),
            (DensityData::F32(g), true) => g.nearest(q),
            (DensityData::Analytic(a), _) => a.density(q / a.n as f32),
        };
        match self.channels.as_slice() {
            [c] => Vec3::splat(one(c)),
            [r, g, b] => Vec3::new(one(r), one(g), one(b)),
            _ => unreachable!("fields have one or three channels"),
        }
    }
}

/// The channel grids of a field: three for an RGB source, else the first.
fn rgb_or_scalar(
    channels: u32,
    grids: impl Iterator<Item = fogbank_volume::Result<BrickGrid<f32>>>,
    key: &str,
) -> Result<Vec<DensityData>, SceneError> {
    let n = if channels == 3 { 3 } else { 1 };
    grids
        .take(n)
        .map(|g| {
            g.map(|g| DensityData::from_f32(g, Precision::F32))
                .map_err(|e| SceneError(format!("{key}: {e}")))
        })
        .collect()
}

fn analytic_kind(name: &str, d: &FieldDesc, key: &str) -> Result<AnalyticKind, SceneError> {
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
                "{key}.procedural: unknown procedural medium `{other}` (cloud, bunny, explosion, plume, constant, ramp, sinusoid, slabs, sphere, empty)"
            )))
        }
    })
}

/// Loads the field `d` (scene key `key`). Values that `precision` cannot
/// hold are refused rather than stored as infinities.
pub fn field_data(
    d: &FieldDesc,
    key: &str,
    base: &Path,
    precision: Precision,
) -> Result<FieldData, SceneError> {
    let field = read_field_data(d, key, base, precision)?;
    if !field.data.stored_values_are_finite() {
        let parent = key.rsplit_once('.').map_or(key, |(p, _)| p);
        return Err(SceneError(match precision {
            Precision::F16 => format!(
                "{key}: {} has values beyond the range of f16 storage (±65504); \
                 set {parent}.precision = \"f32\" (or scale the values down and sigma_t_scale up)",
                field.source
            ),
            Precision::F32 => format!("{key}: {} has values that are not finite", field.source),
        }));
    }
    Ok(field)
}

fn read_field_data(
    d: &FieldDesc,
    key: &str,
    base: &Path,
    precision: Precision,
) -> Result<FieldData, SceneError> {
    let sources = d.files.0.len() + d.array.is_some() as usize + d.procedural.is_some() as usize;
    if sources != 1 {
        let keys: Vec<String> = (formats::all().iter().map(|f| f.key))
            .chain(["array", "procedural"])
            .map(|k| format!("`{k}`"))
            .collect();
        return Err(SceneError(format!(
            "{key}: give exactly one of {}",
            keys.join(", ")
        )));
    }
    if d.quantity.is_some() && d.procedural.as_deref() != Some("explosion") {
        return Err(SceneError(format!(
            "{key}.quantity: only used with procedural = \"explosion\""
        )));
    }
    if d.time.is_some() && d.procedural.as_deref() != Some("plume") {
        return Err(SceneError(format!(
            "{key}.time: only used with procedural = \"plume\""
        )));
    }
    if let Some((format, f)) = d.files.source() {
        let path = base.join(f);
        let source = FileSource {
            key,
            path: &path,
            grid: d.grid.as_deref(),
            level_set: d.level_set.as_deref(),
            channel: d.channel,
            dims: d.dims,
            ty: d.ty.as_deref(),
        };
        return (format.read)(&source, precision).map_err(|e| SceneError(e.to_string()));
    }
    if let Some(name) = &d.array {
        return array_field(d, name, key, precision);
    }
    procedural_field(d, key, precision)
}

/// An in-memory voxel array, as a `.vol` file with the same voxels and box reads.
fn array_field(
    d: &FieldDesc,
    name: &str,
    key: &str,
    precision: Precision,
) -> Result<FieldData, SceneError> {
    let err = volume_error(key);
    // As a `.vol` file with the same voxels and box reads.
    let a = arrays::get(name, key)?;
    let grid = a
        .channel_grid(d.channel.unwrap_or(0))
        .map_err(err)?
        .map_values(|x| x.max(0.0));
    Ok(FieldData::new(
        DensityData::from_f32(grid, precision),
        a.index_to_world(),
        a.describe(),
    ))
}

/// A volume reader's error as a scene error naming the key.
fn volume_error(key: &str) -> impl Fn(fogbank_volume::VolumeError) -> SceneError + Copy + '_ {
    move |e| SceneError(format!("{key}: {e}"))
}

/// A procedural or analytic field of `resolution`³ voxels in the unit box.
fn procedural_field(
    d: &FieldDesc,
    key: &str,
    precision: Precision,
) -> Result<FieldData, SceneError> {
    let err = volume_error(key);
    let name = d.procedural.as_deref().unwrap_or_default();
    let res = d.resolution.unwrap_or(128);
    // Seeded noise shapes with no options beyond resolution and seed.
    type Shape = fn(u32, u64) -> fogbank_volume::Result<BrickGrid<f32>>;
    let shape: Option<Shape> = match name {
        "cloud" => Some(procedural::cloud_grid),
        "bunny" => Some(bunny::bunny_grid),
        _ => None,
    };
    if let Some(build) = shape {
        let grid = build(res, d.seed.unwrap_or(7)).map_err(err)?;
        return Ok(FieldData::new(
            DensityData::from_f32(grid, precision),
            unit_box_transform([res; 3]),
            format!("procedural {name} {res}³"),
        ));
    }
    if name == "explosion" {
        let q = d.quantity.as_deref().unwrap_or("density");
        let quantity = explosion::Quantity::parse(q).ok_or_else(|| {
            SceneError(format!(
                "{key}.quantity: `{q}` is not density or temperature"
            ))
        })?;
        let grid: BrickGrid<f32> =
            explosion::explosion_grid(res, d.seed.unwrap_or(7), quantity).map_err(err)?;
        return Ok(FieldData::new(
            DensityData::from_f32(grid, precision),
            unit_box_transform([res; 3]),
            format!("procedural explosion {q} {res}³"),
        ));
    }
    if name == "plume" {
        let t = d.time.unwrap_or(0.0);
        if !t.is_finite() {
            return Err(SceneError(format!("{key}.time: must be finite")));
        }
        let grid: BrickGrid<f32> = plume::plume_grid(res, d.seed.unwrap_or(7), t).map_err(err)?;
        return Ok(FieldData::new(
            DensityData::from_f32(grid, precision),
            unit_box_transform([res; 3]),
            format!("procedural plume {res}³ at {t} s"),
        ));
    }
    let field = AnalyticField::new(analytic_kind(name, d, key)?, res).map_err(err)?;
    Ok(FieldData::new(
        DensityData::Analytic(field),
        unit_box_transform([res; 3]),
        format!("analytic {name}"),
    ))
}

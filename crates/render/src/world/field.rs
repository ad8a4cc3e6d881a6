//! Spatially varying medium properties other than extinction (albedo,
//! emission colour, temperature): a grid placed in the world like the
//! density, looked up with trilinear interpolation at scattering vertices.

use super::arrays;
use crate::error::SceneError;
use fogbank_math::{DAffine3, Vec3};
use fogbank_volume::loaders::{self as scalar_files, nanovdb, raw, vdb, vdb_grid, vol};
use fogbank_volume::{
    bunny, explosion, medium::unit_box_transform, plume, procedural, AnalyticField, AnalyticKind,
    BrickGrid, DensityData, Precision,
};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The source of a scalar field (density, albedo, emission, temperature).
/// Exactly one source key: `vdb`, `nvdb`, `vol`, `raw`, `nifti`, `nrrd`,
/// `array` or `procedural`.
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
#[serde(deny_unknown_fields)]
pub struct FieldDesc {
    pub vdb: Option<String>,
    /// A NanoVDB file; `grid` and `level_set` as for `vdb`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nvdb: Option<String>,
    pub grid: Option<String>,
    pub level_set: Option<String>,
    pub vol: Option<String>,
    pub channel: Option<u32>,
    pub raw: Option<String>,
    /// A NIfTI-1/2 file (`.nii`, `.nii.gz`, `.hdr`); `channel` picks the 3D
    /// volume of a 4D file. Placed by its sform/qform (RAS millimetres).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nifti: Option<String>,
    /// A NRRD file (`.nrrd`, `.nhdr`); `channel` picks the entry of a
    /// non-spatial axis. Placed by `space directions`/`space origin` (RAS).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nrrd: Option<String>,
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
        let (channels, file_xf, source) = match (&d.vol, &d.array) {
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

/// A loaded field: its data, index→world transform and a description of
/// its source.
pub struct FieldData {
    pub data: DensityData,
    pub to_world: DAffine3,
    pub source: String,
    /// The file's value range (lo, hi) that the stored [0, 1] stands for
    /// (scientific files); `None` when the stored values are the file's.
    pub units: Option<(f32, f32)>,
}

impl FieldData {
    fn new(data: DensityData, to_world: DAffine3, source: String) -> Self {
        FieldData {
            data,
            to_world,
            source,
            units: None,
        }
    }
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
    let sources = [
        d.vdb.is_some(),
        d.nvdb.is_some(),
        d.vol.is_some(),
        d.raw.is_some(),
        d.nifti.is_some(),
        d.nrrd.is_some(),
        d.array.is_some(),
        d.procedural.is_some(),
    ];
    if sources.iter().filter(|&&s| s).count() != 1 {
        return Err(SceneError(format!(
            "{key}: give exactly one of `vdb`, `nvdb`, `vol`, `raw`, `nifti`, `nrrd`, `array`, `procedural`"
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
    if let Some(f) = d.vdb.as_ref().or(d.nvdb.as_ref()) {
        let path = base.join(f);
        let read = if d.vdb.is_some() {
            vdb_field
        } else {
            nvdb_field
        };
        let (data, xf, name) = read(d, &path, key, precision)?;
        let what = format!("{} ({name})", path.display());
        return Ok(FieldData::new(data, xf, what));
    }
    if let Some(f) = &d.vol {
        return vol_field(d, f, key, base, precision);
    }
    if let Some(name) = &d.array {
        return array_field(d, name, key, precision);
    }
    if let Some(f) = &d.raw {
        return raw_field(d, f, key, base, precision);
    }
    if let Some(f) = &d.nifti {
        return scalar_file_field(d, f, true, key, base, precision);
    }
    if let Some(f) = &d.nrrd {
        return scalar_file_field(d, f, false, key, base, precision);
    }
    procedural_field(d, key, precision)
}

/// A volume reader's error as a scene error naming the key.
fn volume_error(key: &str) -> impl Fn(fogbank_volume::VolumeError) -> SceneError + Copy + '_ {
    move |e| SceneError(format!("{key}: {e}"))
}

/// A grid's voxels, its index → world map and its name.
type GridField = (DensityData, DAffine3, String);

/// An OpenVDB grid, its leaves the bricks (level sets as fog unless `raw`).
fn vdb_field(
    d: &FieldDesc,
    path: &Path,
    key: &str,
    precision: Precision,
) -> Result<GridField, SceneError> {
    let err = volume_error(key);
    let g = vdb::read_grid(path, d.grid.as_deref()).map_err(err)?;
    let mode = level_set_mode(d, &g, key)?;
    let name = g.name.clone();
    let map = value_map(&g, mode);
    // The file's leaves become the builder's bricks, and each brick is
    // mapped and stored in the medium's precision as it is finished:
    // the voxels exist in f32 once.
    let (builder, xf) = vdb_grid::to_builder(g).map_err(err)?;
    let data = match precision {
        Precision::F16 => DensityData::F16(builder.finish_converted(map)),
        Precision::F32 => DensityData::F32(builder.finish_converted(map)),
    };
    Ok((data, xf, name))
}

/// A NanoVDB file's float grid, its leaves streamed from the file into
/// bricks of the medium's precision (the same bricks [`vdb_field`] makes
/// of the grid, without ever holding the file's voxels).
fn nvdb_field(
    d: &FieldDesc,
    path: &Path,
    key: &str,
    precision: Precision,
) -> Result<GridField, SceneError> {
    let err = volume_error(key);
    let grid = d.grid.as_deref();
    let mut mode = Ok(false);
    let choose = |g: &vdb::VdbGrid| {
        mode = level_set_mode(d, g, key);
        value_map(g, *mode.as_ref().unwrap_or(&false))
    };
    let (data, xf, g) = match precision {
        Precision::F16 => {
            let (b, xf, g) = nanovdb::read_grid_bricks(path, grid, choose).map_err(err)?;
            (DensityData::F16(b), xf, g)
        }
        Precision::F32 => {
            let (b, xf, g) = nanovdb::read_grid_bricks(path, grid, choose).map_err(err)?;
            (DensityData::F32(b), xf, g)
        }
    };
    mode?;
    Ok((data, xf, g.name))
}

/// Whether a grid is read as a fog volume from a level set (`level_set =
/// "fog"`, the default) rather than as its raw values (`"raw"`).
fn level_set_mode(d: &FieldDesc, g: &vdb::VdbGrid, key: &str) -> Result<bool, SceneError> {
    let level_set = vdb_grid::is_level_set(g);
    let mode = d.level_set.as_deref().unwrap_or("fog");
    if level_set && mode != "fog" && mode != "raw" {
        return Err(SceneError(format!(
            "{key}.level_set: `{mode}` is not `fog` or `raw`"
        )));
    }
    Ok(level_set && mode == "fog")
}

/// The map of a grid's values to densities: a level set's fog, or the
/// values clamped to be non-negative.
fn value_map(g: &vdb::VdbGrid, to_fog: bool) -> impl Fn(f32) -> f32 + Sync + Copy {
    let fog = vdb_grid::level_set_fog(g.background);
    move |v: f32| if to_fog { fog(v) } else { v.max(0.0) }
}

/// A Mitsuba `.vol` file's channel.
fn vol_field(
    d: &FieldDesc,
    f: &str,
    key: &str,
    base: &Path,
    precision: Precision,
) -> Result<FieldData, SceneError> {
    let err = volume_error(key);
    let path = base.join(f);
    let v = vol::read_vol(&path).map_err(err)?;
    let grid = v
        .channel_grid(d.channel.unwrap_or(0))
        .map_err(err)?
        .map_values(|x| x.max(0.0));
    Ok(FieldData::new(
        DensityData::from_f32(grid, precision),
        v.index_to_world(),
        path.display().to_string(),
    ))
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

/// A headerless raw file in the unit box.
fn raw_field(
    d: &FieldDesc,
    f: &str,
    key: &str,
    base: &Path,
    precision: Precision,
) -> Result<FieldData, SceneError> {
    let err = volume_error(key);
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
    Ok(FieldData::new(
        DensityData::from_f32(grid, precision),
        xf,
        path.display().to_string(),
    ))
}

/// A NIfTI or NRRD volume, its value range mapped onto [0, 1].
fn scalar_file_field(
    d: &FieldDesc,
    f: &str,
    nifti: bool,
    key: &str,
    base: &Path,
    precision: Precision,
) -> Result<FieldData, SceneError> {
    let err = volume_error(key);
    let path = base.join(f);
    let index = d.channel.unwrap_or(0);
    let v = if nifti {
        scalar_files::nifti::read(&path, index)
    } else {
        scalar_files::nrrd::read(&path, index)
    }
    .map_err(err)?;
    // The value range maps onto [0, 1]; a transfer function's points
    // (in file units) are mapped the same way.
    let grid = v.normalised_grid().map_err(err)?;
    Ok(FieldData {
        units: Some(v.range().unwrap_or((0.0, 1.0))),
        ..FieldData::new(
            DensityData::from_f32(grid, precision),
            v.index_to_world,
            format!("{} ({})", path.display(), v.description),
        )
    })
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

//! A medium's velocity field, for temporal reprojection of frame sequences
//! (Lin et al. 2021 §4.4: a vertex is moved back along the volume's velocity
//! before it is projected with the previous camera). Velocities are world
//! lengths per second; a frame lasts 1/`animation.fps`.
//!
//! | key | meaning |
//! |---|---|
//! | `vdb = "f_{frame:04}.vdb"` | a `vec3s` grid (float or half, any compression), taken as vectors in the file's world space (OpenVDB's `is_in_world_space`, as Houdini and Blender write velocities), units per second, turned by the medium's `to_world`; `grid` names it (default `vel`, `v`, `velocity`, else the first vec3s grid) |
//! | `nvdb = "f_{frame:04}.nvdb"` | a NanoVDB `Vec3f` or `Vec3d` grid (uncompressed, ZIP or BLOSC), taken as for `vdb`; `grid` names it (default `vel`, `v`, `velocity`, else the first vector grid) |
//! | `array = "array:3"` | an in-memory 3-channel array (`fogbank.Grid` of shape (z, y, x, 3) from numpy), placed by its own box and the medium's `to_world`, vectors in that box's world space, units per second |
//! | `constant = [x, y, z]` | the same velocity everywhere (world units per second) |
//! | `procedural = "plume"` | the analytic velocity of `density = { procedural = "plume" }` (its default) |
//!
//! Without a `velocity` key a medium is still, apart from its `to_world`
//! keys, except a procedural plume, which moves with its own velocity.

use super::field::{Field, FieldDesc};
use crate::error::SceneError;
use fogbank_math::{DAffine3, DVec3, Vec3};
use fogbank_volume::loaders::{nanovdb, vdb, vdb_grid};
use fogbank_volume::{plume, DensityData, Precision};
use glam::Mat3;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct VelocityDesc {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vdb: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nvdb: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grid: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub array: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constant: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub procedural: Option<String>,
}

#[derive(Clone, Debug)]
pub enum Velocity {
    Constant(Vec3),
    /// x, y, z components (one-channel fields placed like the density) and
    /// the linear map turning file vectors into world vectors.
    Grid {
        field: Field,
        to_world: Mat3,
    },
    /// The plume's analytic field: world → unit-cube coordinates and the
    /// linear map of unit-cube vectors to world vectors.
    Plume {
        world_to_unit: DAffine3,
        unit_to_world: Mat3,
    },
}

impl Velocity {
    /// Velocity at world point `p`, world lengths per second.
    pub fn at(&self, p: Vec3) -> Vec3 {
        match self {
            Velocity::Constant(v) => *v,
            Velocity::Grid { field, to_world } => *to_world * field.eval(p),
            Velocity::Plume {
                world_to_unit,
                unit_to_world,
            } => {
                let x = world_to_unit.transform_point3(p.as_dvec3()).as_vec3();
                if x.cmplt(Vec3::ZERO).any() || x.cmpgt(Vec3::ONE).any() {
                    return Vec3::ZERO;
                }
                *unit_to_world * plume::plume_velocity(x)
            }
        }
    }

    /// The velocity `v` of medium `key` (`None`: the density's own, if it
    /// has one). `placement` is the medium's `to_world`; `density_xf` its
    /// density's full index → world map.
    pub fn build(
        v: Option<&VelocityDesc>,
        density: &FieldDesc,
        key: &str,
        base: &Path,
        placement: DAffine3,
        density_xf: DAffine3,
    ) -> Result<Option<Velocity>, SceneError> {
        let is_plume = density.procedural.as_deref() == Some("plume");
        let plume = || {
            let res = density.resolution.unwrap_or(128) as f64;
            let unit_to_index = DAffine3::from_scale(DVec3::splat(res));
            let unit_xf = density_xf * unit_to_index;
            Velocity::Plume {
                world_to_unit: unit_xf.inverse(),
                unit_to_world: unit_xf.matrix3.as_mat3(),
            }
        };
        let Some(v) = v else {
            return Ok(is_plume.then(plume));
        };
        let key = format!("{key}.velocity");
        let given = [
            v.vdb.is_some(),
            v.nvdb.is_some(),
            v.array.is_some(),
            v.constant.is_some(),
            v.procedural.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(SceneError(format!(
                "{key}: give exactly one of `vdb`, `nvdb`, `array`, `constant`, `procedural`"
            )));
        }
        if v.grid.is_some() && v.vdb.is_none() && v.nvdb.is_none() {
            return Err(SceneError(format!(
                "{key}.grid: only used with `vdb` or `nvdb`"
            )));
        }
        if let Some(c) = v.constant {
            if !c.iter().all(|x| x.is_finite()) {
                return Err(SceneError(format!("{key}.constant: must be finite")));
            }
            return Ok(Some(Velocity::Constant(Vec3::from(c))));
        }
        if let Some(p) = &v.procedural {
            if p != "plume" {
                return Err(SceneError(format!(
                    "{key}.procedural: `{p}` is not a procedural velocity (plume)"
                )));
            }
            if !is_plume {
                return Err(SceneError(format!(
                    "{key}.procedural: \"plume\" needs density = {{ procedural = \"plume\" }}"
                )));
            }
            return Ok(Some(plume()));
        }
        if let Some(name) = &v.array {
            return Ok(Some(array_velocity(name, &key, placement)?));
        }
        let (file, read): (_, Vec3Reader) = match &v.nvdb {
            Some(f) => (f.as_str(), nanovdb::read_vec3_grid),
            None => (v.vdb.as_deref().unwrap_or_default(), vdb::read_vec3_grid),
        };
        let field = vdb_velocity(&base.join(file), v.grid.as_deref(), read, &key, placement)?;
        Ok(Some(Velocity::Grid {
            field,
            to_world: placement.matrix3.as_mat3(),
        }))
    }
}

/// The velocity of a 3-channel in-memory array (`array = "array:3"`).
fn array_velocity(name: &str, key: &str, placement: DAffine3) -> Result<Velocity, SceneError> {
    let a = super::arrays::get(name, key)?;
    if a.channels() != 3 {
        return Err(SceneError(format!(
            "{key}.array: {} has {} value(s) per voxel; a velocity has 3",
            a.describe(),
            a.channels()
        )));
    }
    let channels = (0..3)
        .map(|c| {
            a.channel_grid(c)
                .map(|g| DensityData::from_f32(g, Precision::F32))
                .map_err(|e| SceneError(format!("{key}: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let field = Field::from_channels(channels, placement * a.index_to_world(), a.describe())
        .map_err(|SceneError(e)| SceneError(format!("{key}: {e}")))?;
    Ok(Velocity::Grid {
        field,
        to_world: placement.matrix3.as_mat3(),
    })
}

/// The reader of an OpenVDB or a NanoVDB file's vector grid, as components.
type Vec3Reader = fn(&Path, Option<&str>) -> fogbank_volume::Result<[vdb::VdbGrid; 3]>;

/// The three components of vector grid `grid` (or the file's first) of the
/// OpenVDB or NanoVDB file `path` (read by `read`) as one field placed by
/// `placement`.
fn vdb_velocity(
    path: &Path,
    grid: Option<&str>,
    read: Vec3Reader,
    key: &str,
    placement: DAffine3,
) -> Result<Field, SceneError> {
    let err = |e: fogbank_volume::VolumeError| SceneError(format!("{key}: {e}"));
    let grids = read(path, grid).map_err(err)?;
    let mut channels = Vec::with_capacity(3);
    let mut xf = None;
    let source = format!("{} ({})", path.display(), grids[0].name);
    for g in grids {
        let name = g.name.clone();
        let (grid, gxf) = vdb_grid::to_brick_grid(g).map_err(err)?;
        if xf.is_some_and(|x| x != gxf) {
            return Err(SceneError(format!(
                "{key}: {}: the components of grid `{name}` are laid out differently",
                path.display(),
            )));
        }
        xf = Some(gxf);
        channels.push(DensityData::from_f32(grid, Precision::F32));
    }
    let file_xf = xf.unwrap_or(DAffine3::IDENTITY);
    Field::from_channels(channels, placement * file_xf, source)
        .map_err(|SceneError(e)| SceneError(format!("{key}: {e}")))
}

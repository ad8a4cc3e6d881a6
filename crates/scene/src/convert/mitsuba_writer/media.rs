//! `[[media]]` as Mitsuba `heterogeneous` media over a `gridvolume`, each
//! inside a `cube` with a `null` BSDF spanning its grid's box (unless a
//! shape of the scene already names it as its interior).
//!
//! The density is written as a one-channel `.vol` beside the XML file
//! (`NAME_mediumI.vol`, on the unit cube, placed by the medium's
//! `to_world`), unless it already is one (or a 3-channel one read as RGB
//! extinction, `density_rgb`); procedural media are voxelised at
//! their resolution. `sigma_t_scale` is the medium's `scale`, the albedo
//! an `<rgb>`, the phase `hg` (`isotropic` for g = 0).
//!
//! A constant medium with a per-channel `sigma_t_scale` (chromatic σ_t)
//! is a `constvolume` of the RGB σ_t instead.
//!
//! Refused (an error naming the key): emission, transfer functions,
//! albedo grids, RGB density from anything but a 3-channel `.vol`, per-channel `sigma_t_scale` on a grid,
//! instances, phase functions other than Henyey–Greenstein. Dropped with a
//! note: velocity (motion blur), importance rules (sampling only), the
//! filter (Mitsuba's grids are trilinear; fogbank's default stochastic
//! trilinear has the same expectation).

use super::notes::Notes;
use super::xml::El;
use fogbank_math::{DAffine3, Vec3};
use fogbank_render::error::SceneError;
use fogbank_render::world::field::{field_data, FieldDesc};
use fogbank_render::world::medium::{transform, MediumDesc, SigmaTScale};
use fogbank_volume::medium::box_transform;
use fogbank_volume::{DensityData, Precision};
use std::path::{Path, PathBuf};

/// A written medium: its element, its cube (if it needs one) and where its
/// grid's index box lies in the world.
pub struct Medium {
    pub element: El,
    pub cube: El,
    /// index → world.
    pub to_world: DAffine3,
    pub dims: [u32; 3],
}

impl Medium {
    /// The world box around the medium's grid.
    pub fn world_box(&self) -> fogbank_math::Aabb {
        let d = glam::DVec3::from(self.dims.map(f64::from));
        let mut b = fogbank_math::Aabb::EMPTY;
        for c in 0..8 {
            let corner = glam::DVec3::new(
                if c & 1 == 0 { 0.0 } else { d.x },
                if c & 2 == 0 { 0.0 } else { d.y },
                if c & 4 == 0 { 0.0 } else { d.z },
            );
            let p = self.to_world.transform_point3(corner).as_vec3();
            b = b.union(fogbank_math::Aabb::new(p, p));
        }
        b
    }

    /// Whether world point `p` lies in the medium's box.
    pub fn contains(&self, p: Vec3) -> bool {
        let q = self.to_world.inverse().transform_point3(p.as_dvec3());
        let d = glam::DVec3::from(self.dims.map(f64::from));
        q.cmpge(glam::DVec3::ZERO).all() && q.cmple(d).all()
    }
}

/// Where a written `.vol` goes: its path and the name the XML uses.
pub struct VolTarget {
    pub path: PathBuf,
    pub name: String,
}

fn refuse(key: &str, what: &str) -> SceneError {
    SceneError(format!("{key}: {what} has no Mitsuba counterpart"))
}

/// Refuses what Mitsuba cannot express, notes what is dropped.
fn check(m: &MediumDesc, key: &str, notes: &mut Notes) -> Result<(), SceneError> {
    if m.emission.is_some() {
        return Err(refuse(&format!("{key}.emission"), "an emitting medium"));
    }
    if m.transfer.is_some() {
        return Err(refuse(&format!("{key}.transfer"), "a transfer function"));
    }
    if m.albedo_grid.is_some() {
        return Err(refuse(
            &format!("{key}.albedo_grid"),
            "an albedo grid (fogbank's multiplies `albedo`)",
        ));
    }
    if m.density_rgb && (m.density.files.path_of("vol").is_none() || m.density.channel.is_some()) {
        return Err(refuse(
            &format!("{key}.density_rgb"),
            "an RGB density other than a 3-channel .vol",
        ));
    }
    if !m.instances.is_empty() {
        return Err(refuse(&format!("{key}.instances"), "instancing a medium"));
    }
    if m.phase.ty != "hg" {
        return Err(refuse(
            &format!("{key}.phase"),
            &format!("phase `{}`", m.phase.ty),
        ));
    }
    if m.velocity.is_some() {
        notes.note(format!(
            "{key}.velocity: Mitsuba has no motion blur; dropped"
        ));
    }
    if !m.importance.is_empty() || m.importance_pre.is_some() {
        notes.note(format!(
            "{key}.importance: fogbank's sampling rules (the same image in expectation); dropped"
        ));
    }
    if let Some(f) = m.filter.as_deref().filter(|f| *f == "nearest") {
        notes.note(format!(
            "{key}.filter `{f}`: Mitsuba's grids interpolate trilinearly"
        ));
    }
    Ok(())
}

/// A dense grid's dims and values (x fastest).
type Voxels = ([u32; 3], Vec<f32>);

/// The density's voxels as `(dims, values x-fastest, index→world)`, or
/// `None` for a `.vol` file Mitsuba can read as it is.
fn voxels(
    f: &FieldDesc,
    rgb: bool,
    key: &str,
    base: &Path,
    notes: &mut Notes,
) -> Result<(Option<Voxels>, DAffine3), SceneError> {
    let data = field_data(f, key, base, Precision::F32)?;
    if let Some(v) = f.files.path_of("vol") {
        let path = base.join(v);
        let vol = fogbank_volume::loaders::vol::read_vol(&path)
            .map_err(|e| SceneError(format!("{key}: {e}")))?;
        let whole = (vol.channels == 1 && f.channel.unwrap_or(0) == 0) || rgb;
        if whole {
            return Ok((None, data.to_world));
        }
    }
    let grid = |dims: [u32; 3], at: &dyn Fn(u32, u32, u32) -> f32| {
        let mut v = Vec::with_capacity(dims.iter().map(|&d| d as usize).product());
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    v.push(at(i, j, k));
                }
            }
        }
        (dims, v)
    };
    let g = match &data.data {
        DensityData::F32(g) => grid(g.dims(), &|i, j, k| g.fetch(i as i32, j as i32, k as i32)),
        DensityData::F16(g) => grid(g.dims(), &|i, j, k| g.fetch(i as i32, j as i32, k as i32)),
        DensityData::Analytic(a) => {
            if a.name() != "constant" {
                notes.note(format!(
                    "{key}: the procedural `{}` field voxelised at {}³",
                    a.name(),
                    a.n
                ));
            }
            let n = a.n as f32;
            let c = |i: u32| (i as f32 + 0.5) / n;
            grid([a.n; 3], &|i, j, k| a.density(Vec3::new(c(i), c(j), c(k))))
        }
    };
    Ok((Some(g), data.to_world))
}

/// The σ_t volume of a medium with a grey `sigma_t_scale`: a `gridvolume`
/// over its `.vol`, and its grid's dims and index→world map.
fn grid_volume(
    m: &MediumDesc,
    key: &str,
    base: &Path,
    vol: &VolTarget,
    notes: &mut Notes,
) -> Result<(El, [u32; 3], DAffine3), SceneError> {
    let (written, data_xf) = voxels(
        &m.density,
        m.density_rgb,
        &format!("{key}.density"),
        base,
        notes,
    )?;
    let to_world = transform(&m.to_world) * data_xf;
    let (dims, file) = match written {
        Some((dims, values)) => {
            let unit = [0., 0., 0., 1., 1., 1.];
            fogbank_volume::loaders::vol::write_vol(&vol.path, dims, 1, unit, &values)
                .map_err(|e| SceneError(format!("{}: {e}", vol.path.display())))?;
            (dims, vol.name.clone())
        }
        None => {
            let name = m.density.files.path_of("vol").cloned().unwrap_or_default();
            let v = fogbank_volume::loaders::vol::read_vol(&base.join(&name))
                .map_err(|e| SceneError(format!("{key}: {e}")))?;
            (v.dims, name)
        }
    };
    let volume = El::plugin("volume", "gridvolume")
        .attr("name", "sigma_t")
        .child(El::string("filename", &file))
        .child(El::matrix("to_world", rows(unit_to_world(to_world, dims))));
    Ok((volume, dims, to_world))
}

/// Mitsuba places a volume's unit cube by its `to_world`.
fn unit_to_world(to_world: DAffine3, dims: [u32; 3]) -> DAffine3 {
    to_world * box_transform(dims, [0.0; 3], [1.0; 3]).inverse()
}

/// The σ_t volume of a constant medium with a per-channel `sigma_t_scale`
/// (Mitsuba's `scale` is one number): a `constvolume` of the RGB σ_t.
fn chromatic_volume(
    m: &MediumDesc,
    key: &str,
    base: &Path,
    c: [f32; 3],
) -> Result<(El, [u32; 3], DAffine3), SceneError> {
    let data = field_data(&m.density, &format!("{key}.density"), base, Precision::F32)?;
    let DensityData::Analytic(a) = &data.data else {
        return Err(refuse(
            &format!("{key}.sigma_t_scale"),
            "a per-channel scale of a grid (Mitsuba's `scale` is one number)",
        ));
    };
    let v = a.density(Vec3::splat(0.5));
    if a.name() != "constant" {
        return Err(refuse(
            &format!("{key}.sigma_t_scale"),
            "a per-channel scale of a non-constant field",
        ));
    }
    let (dims, to_world) = ([a.n; 3], transform(&m.to_world) * data.to_world);
    let volume = El::plugin("volume", "constvolume")
        .attr("name", "sigma_t")
        .child(El::rgb("value", c.map(|x| x * v)))
        .child(El::matrix("to_world", rows(unit_to_world(to_world, dims))));
    Ok((volume, dims, to_world))
}

/// Medium `i` of the scene as `<medium id="mediumI">`, its `.vol` written
/// to `vol` when it needs one.
pub fn medium(
    m: &MediumDesc,
    i: usize,
    base: &Path,
    vol: &VolTarget,
    notes: &mut Notes,
) -> Result<Medium, SceneError> {
    let key = format!("media.{i}");
    check(m, &key, notes)?;
    m.to_world.check(&format!("{key}.to_world"))?;
    let (volume, scale, dims, to_world) = match m.sigma_t_scale {
        SigmaTScale::Grey(s) => {
            let (v, dims, xf) = grid_volume(m, &key, base, vol, notes)?;
            (v, s, dims, xf)
        }
        SigmaTScale::Rgb(c) => {
            let (v, dims, xf) = chromatic_volume(m, &key, base, c)?;
            (v, 1.0, dims, xf)
        }
    };
    let albedo = m.albedo.unwrap_or([0.8; 3]);
    let id = format!("medium{i}");
    let mut e = El::plugin("medium", "heterogeneous")
        .attr("id", &id)
        .child(volume)
        .child(El::float("scale", scale as f64))
        .child(El::rgb("albedo", albedo));
    e.push(if m.phase.g == 0.0 {
        El::plugin("phase", "isotropic")
    } else {
        El::plugin("phase", "hg").child(El::float("g", m.phase.g as f64))
    });
    let d = glam::DVec3::from(dims.map(f64::from));
    let cube_xf = to_world
        * DAffine3::from_scale_rotation_translation(0.5 * d, glam::DQuat::IDENTITY, 0.5 * d);
    let cube = El::plugin("shape", "cube")
        .child(El::matrix("to_world", rows(cube_xf)))
        .child(El::plugin("bsdf", "null"))
        .child(El::new("ref").attr("name", "interior").attr("id", &id));
    Ok(Medium {
        element: e,
        cube,
        to_world,
        dims,
    })
}

/// An affine map as the rows of a 4×4 matrix.
pub fn rows(a: DAffine3) -> [[f64; 4]; 4] {
    fogbank_volume::writers::rows(&a)
}

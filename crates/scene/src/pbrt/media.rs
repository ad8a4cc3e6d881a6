//! `MakeNamedMedium` as `[[media]]` tables.
//!
//! - σ_a and σ_s (1, 1) times `scale` give fogbank's
//!   `sigma_t_scale` = scale·(σ_a + σ_s) (one number, or one per channel
//!   when they differ) and `albedo` = σ_s / (σ_a + σ_s); `g` is the HG
//!   phase's.
//! - `homogeneous`: pbrt's fills all space a shape's `MediumInterface` (or
//!   the camera) puts it in; fogbank's media are bounded, so it becomes a
//!   constant grid over the box of the shapes it is the inside of, or the
//!   scene's box (a little enlarged) when it is an outside or the camera's
//!   medium. `Le` (an illuminant spectrum, an rgb as is) × `Lescale` is
//!   its emission. `preset` is refused.
//! - `nanovdb`: `filename` (required), `gridname` ("density") as the
//!   density's `nvdb` grid, placed by the grid's own index→world map under
//!   the transform current at `MakeNamedMedium`. pbrt samples at integer
//!   index coordinates, fogbank at cell centres with the half-voxel shift
//!   in the grid's transform, so both place each voxel's value at the same
//!   point. `temperaturename` ("temperature"), when the file has that grid,
//!   gives blackbody emission: `Lescale`·B((T − `temperatureoffset` (else
//!   `temperaturecutoff`))·`temperaturescale`), B normalised to peak 1
//!   (`LeScale`, as pbrt-v4-scenes' explosion spells it, is read as
//!   `Lescale` with a notice),
//!   zero at or below 100 K, as fogbank's `emission.temperature` does.
//! - `uniformgrid`: `density` (nx·ny·nz values, x fastest) over the box
//!   `p0`–`p1` (0–1) under the current transform, cell-centred as pbrt
//!   looks it up, as an in-memory array ([`super::grids`]); the medium
//!   exists in that box. Near the box's faces pbrt interpolates towards
//!   zero outside, fogbank towards the edge value (within half a voxel).
//!   Its emission (`Le`, `Lescale`, `temperature`) is refused.
//! - `rgbgrid`: per-voxel σ_a, σ_s and `Le` as in-memory arrays
//!   ([`super::rgbgrid`]).
//! - `cloud`: pbrt's procedural density baked into an in-memory grid, with
//!   a notice ([`super::cloud`]).

use super::cursor::resolve;
use super::grids::grid_box;
use super::interpret::Placed;
use super::params::ParamList;
use super::spectra::{spectrum, Role};
use super::tables::{matrix_table, set_array_density};
use super::warnings::Warnings;
use fogbank_math::Aabb;
use fogbank_render::error::SceneError;
use glam::{DMat4, DVec3};
use std::path::Path;
use toml::{Table, Value};

fn rgb_value(c: [f64; 3]) -> Value {
    Value::Array(c.iter().map(|&x| Value::Float(x)).collect())
}

/// σ_t and albedo from σ_a, σ_s and scale.
fn extinction(ps: &ParamList, t: &mut Table) -> Result<(), SceneError> {
    let sa = spectrum(ps, "sigma_a", Role::Unbounded)?.unwrap_or([1.0; 3]);
    let ss = spectrum(ps, "sigma_s", Role::Unbounded)?.unwrap_or([1.0; 3]);
    let scale = ps.float("scale", 1.0)?;
    let st: [f64; 3] = std::array::from_fn(|i| sa[i] + ss[i]);
    let albedo: [f64; 3] = std::array::from_fn(|i| if st[i] > 0.0 { ss[i] / st[i] } else { 0.0 });
    let sigma = if st[0] == st[1] && st[1] == st[2] {
        Value::Float(st[0] * scale)
    } else {
        rgb_value(st.map(|x| x * scale))
    };
    t.insert("sigma_t_scale".into(), sigma);
    t.insert("albedo".into(), rgb_value(albedo));
    phase(ps, t)
}

/// The HG phase of `g` (0).
fn phase(ps: &ParamList, t: &mut Table) -> Result<(), SceneError> {
    let g = ps.float("g", 0.0)?;
    if !(-1.0 < g && g < 1.0) {
        return Err(SceneError(format!("g = {g} outside (−1, 1)")));
    }
    let mut ph = Table::new();
    ph.insert("type".into(), "hg".into());
    ph.insert("g".into(), g.into());
    t.insert("phase".into(), Value::Table(ph));
    Ok(())
}

/// The medium `m` (named `name`); `bounds` is where a homogeneous one must
/// exist.
pub fn medium(
    name: &str,
    m: &Placed,
    bounds: Aabb,
    top_dir: &Path,
    warnings: &mut Warnings,
) -> Result<Table, SceneError> {
    let e = &m.entity;
    let ps = &e.params;
    let what = format!("MakeNamedMedium \"{name}\" (\"{}\")", e.ty);
    let mut t = Table::new();
    let located = |err: String| e.loc.error(format!("{what}: {err}"));
    match e.ty.as_str() {
        "rgbgrid" => phase(ps, &mut t).map_err(|err| located(err.0))?,
        // pbrt's cloud reads no `scale` (it would be an unused parameter).
        "cloud" if ps.has("scale") => return Err(located("has no \"scale\"".into())),
        _ => extinction(ps, &mut t).map_err(|err| located(err.0))?,
    }
    match e.ty.as_str() {
        "homogeneous" => homogeneous(ps, bounds, &mut t, warnings, &what)?,
        "nanovdb" => nanovdb(m, top_dir, &mut t, warnings)?,
        "uniformgrid" => uniform_grid(m, &mut t).map_err(located)?,
        "rgbgrid" => super::rgbgrid::rgb_grid(m, &mut t, warnings).map_err(located)?,
        "cloud" => super::cloud::cloud(m, &mut t, warnings).map_err(located)?,
        other => {
            return Err(e
                .loc
                .error(format!("{what}: unknown medium type \"{other}\"")))
        }
    }
    ps.string("type")?;
    t.insert("precision".into(), "f32".into());
    ps.finish(&what)?;
    Ok(t)
}

fn homogeneous(
    ps: &ParamList,
    b: Aabb,
    t: &mut Table,
    warnings: &mut Warnings,
    what: &str,
) -> Result<(), SceneError> {
    if ps.has("preset") {
        ps.string("preset")?;
        return Err(SceneError(format!(
            "{what}: named presets are not supported; give sigma_a and sigma_s"
        )));
    }
    let (lo, hi) = (b.min.as_dvec3(), b.max.as_dvec3());
    let xf = DMat4::from_translation(0.5 * (lo + hi))
        * DMat4::from_scale((hi - lo).max(DVec3::splat(1e-6)));
    let mut d = Table::new();
    d.insert("procedural".into(), "constant".into());
    d.insert("resolution".into(), 2.into());
    t.insert("density".into(), Value::Table(d));
    t.insert("to_world".into(), Value::Table(matrix_table(xf)));
    warnings.warn(format!("{what}: pbrt's unbounded homogeneous medium is a constant grid over its shapes' (or the scene's) box"));
    let le = spectrum(ps, "Le", Role::Illuminant)?;
    let le_scale = ps.float("Lescale", 1.0)?;
    if let Some(c) = le.filter(|c| c.iter().any(|&x| x > 0.0)) {
        let mut em = Table::new();
        em.insert("color".into(), rgb_value(c));
        em.insert("scale".into(), le_scale.into());
        t.insert("emission".into(), Value::Table(em));
    }
    Ok(())
}

fn uniform_grid(m: &Placed, t: &mut Table) -> Result<(), String> {
    let ps = &m.entity.params;
    for k in ["Le", "Lescale", "temperature"] {
        if ps.has(k) {
            return Err(format!(
                "emission (\"{k}\") of a uniform grid is not supported"
            ));
        }
    }
    let (n, p0, p1) = grid_box(ps)?;
    let d = ps
        .nums("float", "density")
        .ok_or("needs \"float density\"")?;
    let count = n.iter().map(|&v| v as u64).product::<u64>();
    if d.len() as u64 != count {
        return Err(format!(
            "{} density values for {}×{}×{}",
            d.len(),
            n[0],
            n[1],
            n[2]
        ));
    }
    let source = format!("{} uniformgrid", m.entity.loc);
    let name = super::grids::register(n, 1, d, p0, p1, &source)?;
    set_array_density(t, name, m.ctm);
    Ok(())
}

fn nanovdb(
    m: &Placed,
    top_dir: &Path,
    t: &mut Table,
    warnings: &mut Warnings,
) -> Result<(), SceneError> {
    let e = &m.entity;
    let ps = &e.params;
    let file = ps
        .string("filename")?
        .ok_or_else(|| e.loc.error("medium \"nanovdb\" needs \"string filename\""))?;
    let path = resolve(file, &e.loc, top_dir);
    let grids = fogbank_volume::loaders::nanovdb::list_grids(&path)
        .map_err(|err| e.loc.error(format!("{}: {err}", path.display())))?;
    let file_str = path.display().to_string();
    let field = |grid: &str| {
        let mut d = Table::new();
        d.insert("nvdb".into(), file_str.clone().into());
        d.insert("grid".into(), grid.into());
        Value::Table(d)
    };
    let density = ps.string("gridname")?.unwrap_or("density");
    t.insert("density".into(), field(density));
    t.insert("to_world".into(), Value::Table(matrix_table(m.ctm)));
    t.insert("filter".into(), "trilinear".into());
    let temp = ps.string("temperaturename")?.unwrap_or("temperature");
    let le_scale = match ps.one("float", "LeScale")? {
        // pbrt-v4-scenes' explosion spells it so; pbrt-v4 itself reads
        // only `Lescale`.
        Some(v) if !ps.has("Lescale") => {
            warnings.warn(format!("{}: \"LeScale\" is read as \"Lescale\"", e.loc));
            v
        }
        _ => ps.float("Lescale", 1.0)?,
    };
    // pbrt reads both; `temperatureoffset` wins.
    let cutoff = ps.float("temperaturecutoff", 0.0)?;
    let offset = ps.float("temperatureoffset", cutoff)?;
    let tscale = ps.float("temperaturescale", 1.0)?;
    if grids.iter().any(|g| g.name == temp) {
        let mut em = Table::new();
        em.insert("temperature".into(), field(temp));
        em.insert("scale".into(), le_scale.into());
        em.insert("temperature_scale".into(), tscale.into());
        em.insert("temperature_offset".into(), offset.into());
        t.insert("emission".into(), Value::Table(em));
    }
    Ok(())
}

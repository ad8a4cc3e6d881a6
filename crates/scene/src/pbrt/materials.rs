//! Materials as fogbank's `bsdf` tables (Mitsuba's BSDFs).
//!
//! - `diffuse`: `reflectance` (0.5) → `diffuse`, two-sided as pbrt's.
//! - `coateddiffuse` → `plastic` (`roughness` 0) or `roughplastic`
//!   (`alpha` = √roughness, pbrt's remapping; GGX), with
//!   `diffuse_reflectance` = `reflectance` and `int_ior` = `eta` (1.5):
//!   pbrt's stochastic layered model (`thickness`, `albedo`, `g`) is
//!   approximated by Mitsuba's plastic, with a notice; a non-zero `albedo`
//!   is refused.
//! - `conductor`: `eta`/`k` as rgb, or pbrt's named `metal-X-eta` and
//!   `metal-X-k` (default Cu) as fogbank's measured metal `X`;
//!   `roughness` (0) → `roughconductor` (α = √roughness unless
//!   `remaproughness` is false). `reflectance` is refused.
//! - `dielectric`: `eta` (1.5, a float; or pbrt's `glass-BK7` as fogbank's
//!   `bk7`, its other named glasses as their d-line index, without
//!   dispersion, with a notice) →
//!   `dielectric`/`roughdielectric`.
//! - `interface` (and the deprecated `""`/`"none"`): `null`, a surface
//!   that only separates media.
//!
//! Textures are refused (a `texture` parameter is never used).

use super::interpret::Entity;
use super::params::{ParamList, Values};
use super::spectra::{spectrum, Role};
use super::warnings::Warnings;
use fogbank_render::error::SceneError;
use toml::{Table, Value};

fn rgb_value(c: [f64; 3]) -> Value {
    Value::Array(c.iter().map(|&x| Value::Float(x)).collect())
}

fn twosided(inner: Table) -> Table {
    let mut t = Table::new();
    t.insert("type".into(), "twosided".into());
    t.insert("bsdf".into(), Value::Table(inner));
    t
}

/// A rough model's α and distribution: pbrt-v4's microfacets are all
/// Trowbridge–Reitz (GGX), while fogbank's rough models default to
/// Mitsuba 3's Beckmann, so the distribution is always written.
fn insert_alpha(t: &mut Table, a: f64) {
    if a > 0.0 {
        t.insert("alpha".into(), a.into());
        t.insert("distribution".into(), "ggx".into());
    }
}

/// pbrt's roughness as a GGX α (pbrt-v4's `RoughnessToAlpha` is √r).
fn alpha(ps: &ParamList) -> Result<f64, SceneError> {
    for k in ["uroughness", "vroughness"] {
        if ps.has(k) {
            ps.one("float", k)?;
            return Err(SceneError(format!(
                "anisotropic roughness (\"{k}\") is not supported; give \"roughness\""
            )));
        }
    }
    let r = ps.float("roughness", 0.0)?;
    let remap = ps.bool("remaproughness", true)?;
    Ok(if remap { r.max(0.0).sqrt() } else { r })
}

/// The material `e` as a `bsdf` table.
pub fn material(e: &Entity, warnings: &mut Warnings) -> Result<Table, SceneError> {
    let what = e.what("Material");
    let t = bsdf(e, warnings).map_err(|err| {
        if err.0.starts_with(&e.loc.to_string()) {
            err
        } else {
            e.loc.error(format!("{what}: {}", err.0))
        }
    })?;
    e.params.string("type")?;
    e.params.finish(&what)?;
    Ok(t)
}

fn bsdf(e: &Entity, warnings: &mut Warnings) -> Result<Table, SceneError> {
    let ps = &e.params;
    let mut t = Table::new();
    match e.ty.as_str() {
        "diffuse" => {
            let r = spectrum(ps, "reflectance", Role::Reflectance)?.unwrap_or([0.5; 3]);
            t.insert("type".into(), "diffuse".into());
            t.insert("reflectance".into(), rgb_value(r));
            Ok(twosided(t))
        }
        "coateddiffuse" => coated(e, warnings),
        "conductor" => conductor(ps).map(twosided),
        "dielectric" => {
            let eta = dielectric_eta(e, warnings)?;
            let a = alpha(ps)?;
            let ty = if a > 0.0 { "roughdielectric" } else { "dielectric" };
            t.insert("type".into(), ty.into());
            t.insert("int_ior".into(), eta);
            t.insert("ext_ior".into(), 1.0.into());
            insert_alpha(&mut t, a);
            Ok(t)
        }
        "interface" | "" | "none" => {
            if e.ty != "interface" {
                warnings.warn(format!("{}: material \"{}\" is a deprecated name of \"interface\"", e.loc, e.ty));
            }
            t.insert("type".into(), "null".into());
            Ok(t)
        }
        other => Err(SceneError(format!(
            "material \"{other}\" is not supported (diffuse, coateddiffuse, conductor, dielectric, interface)"
        ))),
    }
}

fn coated(e: &Entity, warnings: &mut Warnings) -> Result<Table, SceneError> {
    let ps = &e.params;
    let r = spectrum(ps, "reflectance", Role::Reflectance)?.unwrap_or([0.5; 3]);
    let eta = ps.float("eta", 1.5)?;
    if spectrum(ps, "albedo", Role::Reflectance)?.is_some_and(|a| a.iter().any(|&x| x > 0.0)) {
        return Err(SceneError(
            "a coating with a non-zero albedo is not supported".into(),
        ));
    }
    for k in ["thickness", "g"] {
        ps.one("float", k)?;
    }
    for k in ["maxdepth", "nsamples"] {
        ps.one("integer", k)?;
    }
    let a = alpha(ps)?;
    warnings.warn(format!(
        "{}: coateddiffuse is approximated by fogbank's (Mitsuba's) plastic",
        e.loc
    ));
    let mut t = Table::new();
    t.insert(
        "type".into(),
        if a > 0.0 { "roughplastic" } else { "plastic" }.into(),
    );
    t.insert("diffuse_reflectance".into(), rgb_value(r));
    t.insert("int_ior".into(), eta.into());
    t.insert("ext_ior".into(), 1.0.into());
    insert_alpha(&mut t, a);
    Ok(twosided(t))
}

/// pbrt's named glasses other than BK7 (`glass-F5`, `-F10`, `-F11` are its
/// names for Schott's SF5, SF10 and SF11) and their refractive index at
/// the d-line.
const GLASSES: [(&str, f64); 6] = [
    ("glass-BAF10", 1.67003),
    ("glass-FK51A", 1.48656),
    ("glass-LASF9", 1.85025),
    ("glass-F5", 1.67270),
    ("glass-F10", 1.72825),
    ("glass-F11", 1.78472),
];

/// A dielectric's `eta`: a float, or pbrt's named glasses as fogbank's
/// (non-dispersive) IOR of the same name (BK7) or their d-line index.
fn dielectric_eta(e: &Entity, warnings: &mut Warnings) -> Result<Value, SceneError> {
    let ps = &e.params;
    if let Some(n) = named(ps, "eta") {
        if let Some(&(_, nd)) = GLASSES.iter().find(|(g, _)| *g == n) {
            warnings.warn(format!(
                "{}: \"{n}\" is its d-line index {nd} (587.6 nm, Schott's catalogue) without dispersion",
                e.loc
            ));
            return Ok(nd.into());
        }
        if n != "glass-BK7" {
            return Err(SceneError(format!(
                "named spectrum \"{n}\" for eta: only pbrt's named glasses, or a float"
            )));
        }
        let ior = "bk7";
        warnings.warn(format!(
            "{}: \"{n}\" is fogbank's IOR \"{ior}\" without dispersion",
            e.loc
        ));
        return Ok(ior.into());
    }
    if ps.lookup("eta", &["spectrum"]).is_some() {
        return Err(SceneError(
            "a sampled spectrum for eta is not supported (no dispersion); give a float".into(),
        ));
    }
    Ok(ps.float("eta", 1.5)?.into())
}

/// A named spectrum parameter's name, if it is one.
fn named(ps: &ParamList, name: &str) -> Option<String> {
    let p = ps
        .params
        .iter()
        .find(|p| p.name == name && p.ty == "spectrum")?;
    match &p.values {
        Values::Strs(s) => {
            ps.lookup(name, &["spectrum"]);
            Some(s[0].clone())
        }
        _ => None,
    }
}

fn conductor(ps: &ParamList) -> Result<Table, SceneError> {
    if ps.has("reflectance") {
        return Err(SceneError(
            "\"reflectance\" (the artist's conductor) is not supported; give eta and k".into(),
        ));
    }
    let mut t = Table::new();
    let (ne, nk) = (named(ps, "eta"), named(ps, "k"));
    match (ne, nk) {
        (None, None) if !ps.has("eta") && !ps.has("k") => {
            t.insert("material".into(), "Cu".into());
        }
        (Some(e), Some(k)) => {
            let metal = e
                .strip_prefix("metal-")
                .and_then(|s| s.strip_suffix("-eta"));
            let metal_k = k.strip_prefix("metal-").and_then(|s| s.strip_suffix("-k"));
            match (metal, metal_k) {
                (Some(a), Some(b)) if a == b => {
                    t.insert("material".into(), a.into());
                }
                _ => {
                    return Err(SceneError(format!(
                        "named spectra \"{e}\"/\"{k}\": only a pair metal-X-eta, metal-X-k"
                    )))
                }
            }
        }
        _ => {
            let eta = spectrum(ps, "eta", Role::Unbounded)?
                .ok_or_else(|| SceneError("give both eta and k".into()))?;
            let k = spectrum(ps, "k", Role::Unbounded)?
                .ok_or_else(|| SceneError("give both eta and k".into()))?;
            t.insert("eta".into(), rgb_value(eta));
            t.insert("k".into(), rgb_value(k));
        }
    }
    let a = alpha(ps)?;
    t.insert(
        "type".into(),
        if a > 0.0 {
            "roughconductor"
        } else {
            "conductor"
        }
        .into(),
    );
    insert_alpha(&mut t, a);
    Ok(t)
}

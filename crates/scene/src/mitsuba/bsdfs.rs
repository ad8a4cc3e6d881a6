//! `<bsdf>` and `<texture>` elements as fogbank `bsdf` tables: the same
//! plugin names and parameter names (see `world::surfaces::bsdf_desc`).

use super::plugin::{Ids, Plugin};
use super::xml::{Document, Element};
use fogbank_image::spectrum::SpectrumUse;
use fogbank_render::error::SceneError;
use toml::{Table, Value};

pub fn rgb_value(c: [f32; 3]) -> Value {
    Value::Array(c.iter().map(|&x| Value::Float(x as f64)).collect())
}

/// A reflectance parameter: a constant, or a nested/referenced texture.
fn reflectance(
    p: &Plugin,
    name: &str,
    out: &mut Table,
    ids: &Ids,
    doc: &Document,
) -> Result<(), SceneError> {
    if let Some(c) = p.rgb(name, SpectrumUse::Bounded)? {
        out.insert(name.into(), rgb_value(c));
    } else if let Some(t) = p.object("texture", name)? {
        out.insert(name.into(), Value::Table(texture(t, ids, doc)?));
    }
    Ok(())
}

/// `to_uv` as a `{ scale, translate }` table (2-D scale and translation).
fn to_uv(p: &Plugin, t: &mut Table) -> Result<(), SceneError> {
    if let Some(m) = p.transform("to_uv")? {
        let c = m.to_cols_array_2d();
        // A 2-D scale and translation: columns 0, 1 and 3.
        if c[0][1] != 0.0 || c[1][0] != 0.0 {
            return Err(p.error("to_uv: only scale and translate are supported"));
        }
        let mut uv = Table::new();
        uv.insert(
            "scale".into(),
            Value::Array(vec![c[0][0].into(), c[1][1].into()]),
        );
        uv.insert(
            "translate".into(),
            Value::Array(vec![c[3][0].into(), c[3][1].into()]),
        );
        t.insert("to_uv".into(), Value::Table(uv));
    }
    Ok(())
}

fn texture(e: &Element, ids: &Ids, doc: &Document) -> Result<Table, SceneError> {
    let p = Plugin::new(e, ids)?;
    let mut t = Table::new();
    t.insert("type".into(), p.ty.into());
    match p.ty {
        "checkerboard" => {
            for k in ["color0", "color1"] {
                if let Some(c) = p.rgb(k, SpectrumUse::Bounded)? {
                    t.insert(k.into(), rgb_value(c));
                }
            }
        }
        "bitmap" => {
            let path = p.filename(doc)?;
            t.insert("filename".into(), path.display().to_string().into());
            for k in ["filter_type", "wrap_mode"] {
                if let Some(v) = p.string(k)? {
                    t.insert(k.into(), v.into());
                }
            }
            if let Some(b) = p.boolean("raw")? {
                t.insert("raw".into(), b.into());
            }
            // Storage precision: fogbank stores what Mitsuba's "auto" does.
            if let Some(v) = p.string("format")? {
                if v != "auto" {
                    return Err(p.error(format!("format `{v}`: only \"auto\" is supported")));
                }
            }
            // Hardware interpolation exists on Mitsuba's CUDA variants only;
            // its scalar variants (the references) ignore it, as fogbank does.
            p.boolean("accel")?;
        }
        other => {
            return Err(p.error(format!(
                "texture `{other}` is not supported (checkerboard, bitmap)"
            )))
        }
    }
    to_uv(&p, &mut t)?;
    p.finish()?;
    Ok(t)
}

fn ior(p: &Plugin, name: &str, out: &mut Table) -> Result<(), SceneError> {
    if let Some(v) = p.string(name)? {
        out.insert(name.into(), v.into());
    } else if let Some(v) = p.float(name)? {
        out.insert(name.into(), v.into());
    }
    Ok(())
}

/// The microfacet parameters, with Mitsuba's defaults: Beckmann, α 0.1,
/// visible-normal sampling.
fn rough(p: &Plugin, out: &mut Table) -> Result<(), SceneError> {
    let distribution = p.string("distribution")?.unwrap_or("beckmann");
    let distribution = distribution.to_ascii_lowercase();
    if distribution != "beckmann" && distribution != "ggx" {
        return Err(p.error(format!("distribution `{distribution}` (beckmann or ggx)")));
    }
    out.insert("distribution".into(), distribution.into());
    if let Some(v) = p.boolean("sample_visible")? {
        out.insert("sample_visible".into(), v.into());
    }
    if let Some(a) = p.float("alpha")? {
        out.insert("alpha".into(), a.into());
    }
    if p.float("alpha_u")?.is_some() || p.float("alpha_v")?.is_some() {
        return Err(p.error("anisotropic roughness (alpha_u, alpha_v) is not supported"));
    }
    Ok(())
}

/// Refuses a parameter whose only supported value is its default 1.
fn unit_only(p: &Plugin, name: &str) -> Result<(), SceneError> {
    match p.rgb(name, SpectrumUse::Bounded)? {
        None | Some([1.0, 1.0, 1.0]) => Ok(()),
        Some(c) => Err(p.error(format!("{name} = {c:?}: only 1 is supported"))),
    }
}

pub fn bsdf(e: &Element, ids: &Ids, doc: &Document) -> Result<Table, SceneError> {
    let p = Plugin::new(e, ids)?;
    let mut t = Table::new();
    t.insert("type".into(), p.ty.into());
    match p.ty {
        "diffuse" => reflectance(&p, "reflectance", &mut t, ids, doc)?,
        "conductor" | "roughconductor" => {
            if let Some(m) = p.string("material")? {
                t.insert("material".into(), m.into());
            }
            for k in ["eta", "k"] {
                if let Some(c) = p.rgb(k, SpectrumUse::Unbounded)? {
                    t.insert(k.into(), rgb_value(c));
                }
            }
            reflectance(&p, "specular_reflectance", &mut t, ids, doc)?;
            if p.ty == "roughconductor" {
                rough(&p, &mut t)?;
            }
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            ior(&p, "int_ior", &mut t)?;
            ior(&p, "ext_ior", &mut t)?;
            unit_only(&p, "specular_reflectance")?;
            unit_only(&p, "specular_transmittance")?;
            if p.ty == "roughdielectric" {
                rough(&p, &mut t)?;
            }
        }
        "plastic" | "roughplastic" => {
            if p.ty == "roughplastic" {
                rough(&p, &mut t)?;
            }
            reflectance(&p, "diffuse_reflectance", &mut t, ids, doc)?;
            reflectance(&p, "specular_reflectance", &mut t, ids, doc)?;
            ior(&p, "int_ior", &mut t)?;
            ior(&p, "ext_ior", &mut t)?;
            if let Some(b) = p.boolean("nonlinear")? {
                t.insert("nonlinear".into(), b.into());
            }
        }
        "null" => {}
        "twosided" => {
            let sides = p.objects("bsdf")?;
            match sides.as_slice() {
                [one] => {
                    t.insert("bsdf".into(), Value::Table(bsdf(one, ids, doc)?));
                }
                [front, back] => {
                    t.insert("front".into(), Value::Table(bsdf(front, ids, doc)?));
                    t.insert("back".into(), Value::Table(bsdf(back, ids, doc)?));
                }
                _ => return Err(p.error("twosided takes one or two nested BSDFs")),
            }
        }
        other => {
            return Err(p.error(format!(
                "BSDF `{other}` is not supported (diffuse, conductor, roughconductor, dielectric, \
                 roughdielectric, thindielectric, plastic, roughplastic, null, twosided)"
            )))
        }
    }
    p.finish()?;
    Ok(t)
}

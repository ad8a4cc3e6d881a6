//! `<medium>` elements as `[[media]]` tables. A homogeneous medium (or a
//! `constvolume`) becomes a constant grid over `bounds` (its shapes'
//! box, or the scene's when it is unbounded); a `gridvolume` keeps its
//! `.vol` file, placed as Mitsuba places it.

use super::bsdfs::rgb_value;
use super::plugin::{Ids, Plugin};
use super::shapes::matrix_table;
use super::xml::{Document, Element};
use fogbank_image::spectrum::SpectrumUse;
use fogbank_math::Aabb;
use fogbank_render::error::SceneError;
use glam::{DMat4, DVec3};
use toml::{Table, Value};

/// The `.vol` header's channel count and bounding box.
fn vol_header(path: &std::path::Path) -> Result<(u32, DVec3, DVec3), String> {
    use std::io::Read;
    let mut h = [0u8; 48];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut h))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if &h[..3] != b"VOL" {
        return Err(format!("{}: not a .vol file", path.display()));
    }
    let f = |o: usize| f32::from_le_bytes([h[o], h[o + 1], h[o + 2], h[o + 3]]) as f64;
    let channels = i32::from_le_bytes([h[20], h[21], h[22], h[23]]);
    Ok((
        channels.max(0) as u32,
        DVec3::new(f(24), f(28), f(32)),
        DVec3::new(f(36), f(40), f(44)),
    ))
}

/// A grid volume as a `density`-like table and its `to_world` (fogbank
/// places a `.vol` by its file box; Mitsuba by the unit cube unless
/// `use_grid_bbox`), and its channel count.
fn grid(e: &Element, ids: &Ids, doc: &Document) -> Result<(Table, DMat4, u32), SceneError> {
    let p = Plugin::new(e, ids)?;
    if p.ty != "gridvolume" {
        return Err(p.error(format!(
            "volume `{}` is not supported here (gridvolume)",
            p.ty
        )));
    }
    let path = p.filename(doc)?;
    let (channels, lo, hi) = vol_header(&path).map_err(|m| p.error(m))?;
    let m = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    let grid_bbox = p.boolean("use_grid_bbox")?.unwrap_or(false);
    match p.string("filter_type")? {
        None | Some("trilinear") => {}
        Some(other) => return Err(p.error(format!("filter_type `{other}`: only trilinear"))),
    }
    p.finish()?;
    // fogbank's file placement is the box B; Mitsuba's is the unit cube.
    let unit_to_box = DMat4::from_translation(lo) * DMat4::from_scale(hi - lo);
    let xf = if grid_bbox {
        m
    } else {
        m * unit_to_box.inverse()
    };
    let mut t = Table::new();
    t.insert("vol".into(), path.display().to_string().into());
    Ok((t, xf, channels))
}

/// A constant volume's value and its box: Mitsuba's volumes span the unit
/// cube mapped by `to_world` (its axis-aligned bounds), and a
/// heterogeneous medium exists only inside its σ_t volume's box.
fn constant(e: &Element, ids: &Ids) -> Result<Option<([f32; 3], Aabb)>, SceneError> {
    let p = Plugin::new(e, ids)?;
    if p.ty != "constvolume" {
        return Ok(None);
    }
    let v = p.rgb("value", SpectrumUse::Unbounded)?.unwrap_or([1.0; 3]);
    let m = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    p.finish()?;
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for c in 0..8 {
        let corner = DVec3::new((c & 1) as f64, ((c >> 1) & 1) as f64, ((c >> 2) & 1) as f64);
        let w = m.transform_point3(corner);
        lo = lo.min(w);
        hi = hi.max(w);
    }
    Ok(Some((v, Aabb::new(lo.as_vec3(), hi.as_vec3()))))
}

fn phase(p: &Plugin, ids: &Ids, t: &mut Table) -> Result<(), SceneError> {
    let Some(e) = p.object("phase", "")? else {
        return Ok(());
    };
    let ph = Plugin::new(e, ids)?;
    let g = match ph.ty {
        "isotropic" => 0.0,
        "hg" => ph.float("g")?.unwrap_or(0.8),
        other => return Err(ph.error(format!("phase `{other}` is not supported (isotropic, hg)"))),
    };
    ph.finish()?;
    let mut pt = Table::new();
    pt.insert("type".into(), "hg".into());
    pt.insert("g".into(), g.into());
    t.insert("phase".into(), Value::Table(pt));
    Ok(())
}

/// fogbank's `sigma_t_scale` for a constant σ_t of `c` times `scale`: one
/// number when the channels agree, else one per channel (chromatic).
fn sigma_t_scale(c: [f32; 3], scale: f64) -> Value {
    if c[0] == c[1] && c[1] == c[2] {
        (c[0] as f64 * scale).into()
    } else {
        Value::Array(c.iter().map(|&v| (v as f64 * scale).into()).collect())
    }
}

/// The medium over `bounds` (used by constant media only).
pub fn medium(e: &Element, ids: &Ids, doc: &Document, bounds: Aabb) -> Result<Table, SceneError> {
    let p = Plugin::new(e, ids)?;
    let mut t = Table::new();
    let scale = p.float("scale")?.unwrap_or(1.0);
    let box_xf = |b: Aabb| {
        let (lo, hi) = (b.min.as_dvec3(), b.max.as_dvec3());
        DMat4::from_translation(0.5 * (lo + hi))
            * DMat4::from_scale((hi - lo).max(DVec3::splat(1e-6)))
    };
    let constant_density = |t: &mut Table, sigma: [f32; 3], b: Aabb| {
        let mut d = Table::new();
        d.insert("procedural".into(), "constant".into());
        d.insert("resolution".into(), 2.into());
        t.insert("density".into(), Value::Table(d));
        t.insert("sigma_t_scale".into(), sigma_t_scale(sigma, scale));
        t.insert("to_world".into(), Value::Table(matrix_table(box_xf(b))));
    };
    match p.ty {
        "homogeneous" => {
            // Mitsuba 3.9's RGB variants read a spectrum here as a bounded
            // texture, clamped to [0, 1]; fogbank does the same.
            let s = p.rgb("sigma_t", SpectrumUse::Bounded)?.unwrap_or([1.0; 3]);
            constant_density(&mut t, s, bounds);
        }
        "heterogeneous" => {
            let v = p
                .object("volume", "sigma_t")?
                .ok_or_else(|| p.error("needs a `sigma_t` volume"))?;
            if let Some((c, volume_box)) = constant(v, ids)? {
                // Where the shapes that bound it and the volume's box meet.
                let b = Aabb::new(
                    bounds.min.max(volume_box.min),
                    bounds.max.min(volume_box.max),
                );
                if !(b.min.cmplt(b.max).all()) {
                    return Err(v.error(
                        "the constant volume's box (its to_world of the unit cube) misses the shapes that bound the medium",
                    ));
                }
                constant_density(&mut t, c, b);
            } else {
                let (density, xf, channels) = grid(v, ids, doc)?;
                match channels {
                    1 => {}
                    3 => {
                        t.insert("density_rgb".into(), true.into());
                    }
                    n => {
                        return Err(v.error(format!("a {n}-channel sigma_t grid (1 or 3 channels)")))
                    }
                }
                t.insert("density".into(), Value::Table(density));
                t.insert("sigma_t_scale".into(), scale.into());
                t.insert("to_world".into(), Value::Table(matrix_table(xf)));
                t.insert("filter".into(), "trilinear".into());
            }
        }
        other => {
            return Err(p.error(format!(
                "medium `{other}` is not supported (homogeneous, heterogeneous)"
            )))
        }
    }
    albedo(&p, ids, doc, &mut t)?;
    phase(&p, ids, &mut t)?;
    if let Some(b) = p.boolean("sample_emitters")? {
        if !b {
            return Err(p.error("sample_emitters = false is not supported"));
        }
    }
    t.insert("precision".into(), "f32".into());
    p.finish()?;
    Ok(t)
}

fn albedo(p: &Plugin, ids: &Ids, doc: &Document, t: &mut Table) -> Result<(), SceneError> {
    if let Some(c) = p.rgb("albedo", SpectrumUse::Bounded)? {
        t.insert("albedo".into(), rgb_value(c));
    } else if let Some(v) = p.object("volume", "albedo")? {
        if let Some((c, _)) = constant(v, ids)? {
            t.insert("albedo".into(), rgb_value(c));
        } else {
            let (grid, xf, _) = grid(v, ids, doc)?;
            let density_xf = t.get("to_world").cloned();
            if density_xf != Some(Value::Table(matrix_table(xf))) {
                return Err(v.error("an albedo grid must be placed like the sigma_t grid"));
            }
            t.insert("albedo".into(), rgb_value([1.0; 3]));
            t.insert("albedo_grid".into(), Value::Table(grid));
        }
    } else {
        // Mitsuba's default albedo is 0.75.
        t.insert("albedo".into(), rgb_value([0.75; 3]));
    }
    Ok(())
}

//! `Shape` statements as `[[shapes]]` tables (without their material,
//! emitter and media, which the conversion adds).
//!
//! - `sphere`: `radius` (1) → fogbank's analytic sphere; under a
//!   non-uniform scale (an ellipsoid, which fogbank's one-radius sphere
//!   cannot be) a tessellated mesh ([`super::meshes::ellipsoid`]), with a
//!   notice; partial spheres (`zmin`, `zmax`, `phimax`) are refused.
//! - `disk`: `height` (0), `radius` (1) → the analytic unit disk (normal
//!   +z, as pbrt's); `innerradius` and `phimax` are refused.
//! - `plymesh`: `filename` → fogbank's PLY reader; `displacement` is
//!   refused.
//! - `trianglemesh` and `bilinearmesh`: a single planar parallelogram (two
//!   triangles over four points, or one bilinear patch whose corners form
//!   one) without `N` or `uv` → fogbank's rectangle, facing where pbrt's
//!   normal faces (the first triangle's winding; dp/du × dp/dv of the
//!   patch). Other inline meshes become PLY files ([`super::meshes`]).
//!
//! `ReverseOrientation` flips the normals (and so which side is inside a
//! `MediumInterface` and which side an area light lights). A shape
//! transform that mirrors is refused.

use super::cursor::resolve;
use super::interpret::ShapeEntity;
use super::meshes;
use super::params::ParamList;
use super::tables::matrix_table;
use super::warnings::Warnings;
use fogbank_render::error::SceneError;
use glam::{DMat3, DMat4, DVec3};
use std::f64::consts::PI;
use std::path::Path;
use toml::{Table, Value};

/// A shape's table and its area (world units; `None` when not known).
pub struct ShapeOut {
    pub table: Table,
    pub area: Option<f64>,
}

/// The area scale of `m` if it is a rotation times a uniform scale.
fn area_scale(m: DMat4) -> Option<f64> {
    let r = DMat3::from_mat4(m);
    let s2 = r.col(0).length_squared();
    let g = r.transpose() * r;
    g.abs_diff_eq(DMat3::IDENTITY * s2, 1e-6 * s2.max(1e-12))
        .then_some(s2)
}

pub fn shape(
    s: &ShapeEntity,
    top_dir: &Path,
    warnings: &mut Warnings,
) -> Result<ShapeOut, SceneError> {
    let e = &s.entity;
    let ps = &e.params;
    let what = e.what("Shape");
    let err = |m: String| e.loc.error(format!("{what}: {m}"));
    if DMat3::from_mat4(s.ctm).determinant() < 0.0 {
        return Err(err(
            "a mirroring transform is not supported on shapes".into()
        ));
    }
    let mut t = Table::new();
    let (local, area) = match e.ty.as_str() {
        "sphere" => sphere(s, &mut t, warnings).map_err(err)?,
        "disk" => {
            let (h, r) = (ps.float("height", 0.0)?, ps.float("radius", 1.0)?);
            if ps.float("innerradius", 0.0)? != 0.0 || ps.float("phimax", 360.0)? != 360.0 {
                return Err(err("an annulus or partial disk is not supported".into()));
            }
            t.insert("type".into(), "disk".into());
            let m = DMat4::from_translation(DVec3::new(0.0, 0.0, h)) * DMat4::from_scale(DVec3::new(r, r, 1.0));
            (m, Area::Local(PI * r * r))
        }
        "plymesh" => {
            let f = ps.string("filename")?.ok_or_else(|| err("needs \"string filename\"".into()))?;
            t.insert("type".into(), "ply".into());
            t.insert("file".into(), resolve(f, &e.loc, top_dir).display().to_string().into());
            (DMat4::IDENTITY, Area::Unknown)
        }
        "trianglemesh" | "bilinearmesh" => inline_mesh(s, &mut t, warnings).map_err(err)?,
        other => return Err(err(format!("shape \"{other}\" is not supported (sphere, disk, plymesh, trianglemesh and bilinearmesh parallelograms)"))),
    };
    if s.attrs.reverse_orientation {
        t.insert("flip_normals".into(), true.into());
    }
    t.insert("to_world".into(), Value::Table(matrix_table(s.ctm * local)));
    ps.finish(&what)?;
    let area = match area {
        Area::Local(a) => area_scale(s.ctm).map(|k| a * k),
        Area::World(a) => Some(a),
        Area::Unknown => None,
    };
    Ok(ShapeOut { table: t, area })
}

/// A shape's area: in its own space (scaled by the transform when that
/// scales uniformly), in world space, or not known.
enum Area {
    Local(f64),
    World(f64),
    Unknown,
}

/// A `sphere`: fogbank's analytic one, or under a non-uniform scale (which
/// its one radius cannot take) a tessellated ellipsoid.
fn sphere(
    s: &ShapeEntity,
    t: &mut Table,
    warnings: &mut Warnings,
) -> Result<(DMat4, Area), String> {
    let ps = &s.entity.params;
    let r = ps.float("radius", 1.0).map_err(|e| e.0)?;
    for k in ["zmin", "zmax", "phimax"] {
        if ps.has(k) {
            return Err(format!("a partial sphere (\"{k}\") is not supported"));
        }
    }
    let local = DMat4::from_scale(DVec3::splat(r));
    if area_scale(s.ctm).is_some() {
        t.insert("type".into(), "sphere".into());
        return Ok((local, Area::Local(4.0 * PI * r * r)));
    }
    let mesh = meshes::ellipsoid(s.ctm * local);
    let file = meshes::write_cached(&mesh)?;
    warnings.warn(format!(
        "{}: a sphere under a non-uniform scale (an ellipsoid) is tessellated into {} triangles",
        s.entity.loc,
        mesh.tris.len()
    ));
    t.insert("type".into(), "ply".into());
    t.insert("file".into(), file.display().to_string().into());
    // The mesh is in world space already.
    Ok((s.ctm.inverse(), Area::World(mesh.area(DMat4::IDENTITY))))
}

/// A `trianglemesh` or `bilinearmesh`: fogbank's rectangle when it is one
/// parallelogram without normals or uvs, else a cached PLY file.
fn inline_mesh(
    s: &ShapeEntity,
    t: &mut Table,
    warnings: &mut Warnings,
) -> Result<(DMat4, Area), String> {
    let (e, ps) = (&s.entity, &s.entity.params);
    let bilinear = e.ty == "bilinearmesh";
    let simple = !["N", "uv", "faceIndices", "S"].iter().any(|k| ps.has(k));
    if let Some(m) = simple.then(|| parallelogram(ps, bilinear).ok()).flatten() {
        t.insert("type".into(), "rectangle".into());
        let a = 4.0 * m.x_axis.truncate().cross(m.y_axis.truncate()).length();
        return Ok((m, Area::Local(a)));
    }
    let mesh = if bilinear {
        meshes::bilinear_mesh(ps, warnings, &e.loc.to_string())?
    } else {
        meshes::triangle_mesh(ps)?
    };
    let file = meshes::write_cached(&mesh)?;
    t.insert("type".into(), "ply".into());
    t.insert("file".into(), file.display().to_string().into());
    if mesh.n.is_empty() {
        t.insert("face_normals".into(), true.into());
    }
    Ok((DMat4::IDENTITY, Area::World(mesh.area(s.ctm))))
}

/// The points of `P`.
fn points(ps: &ParamList) -> Result<Vec<DVec3>, String> {
    let p = ps.nums("point3", "P").ok_or("needs \"point3 P\"")?;
    Ok(p.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect())
}

/// The map of fogbank's rectangle ([−1, 1]², normal +z) onto a mesh that
/// is one parallelogram.
fn parallelogram(ps: &ParamList, bilinear: bool) -> Result<DMat4, String> {
    let p = points(ps)?;
    let idx: Vec<usize> = match ps.nums("integer", "indices") {
        Some(v) => v.iter().map(|&i| i as usize).collect(),
        None if bilinear && p.len() == 4 => vec![0, 1, 2, 3],
        None => return Err("needs \"integer indices\"".into()),
    };
    if p.len() != 4 || idx.iter().any(|&i| i >= 4) {
        return Err("only a single parallelogram of four points is supported (fogbank reads other meshes from PLY files)".into());
    }
    let (corner, e1, e2, normal) = if bilinear {
        let [a, b, c, d] = idx[..] else {
            return Err("a bilinear patch has 4 indices".into());
        };
        if ((p[a] + p[d]) - (p[b] + p[c])).length() > 1e-6 * (p[d] - p[a]).length() {
            return Err("only a planar parallelogram patch is supported".into());
        }
        (
            p[a],
            (p[b] - p[a]) / 2.0,
            (p[c] - p[a]) / 2.0,
            (p[b] - p[a]).cross(p[c] - p[a]),
        )
    } else {
        triangles(&p, &idx)?
    };
    let n = normal.try_normalize().ok_or("a degenerate parallelogram")?;
    let (e1, e2) = if e1.cross(e2).dot(n) > 0.0 {
        (e1, e2)
    } else {
        (e2, e1)
    };
    let centre = corner + e1 + e2;
    Ok(DMat4::from_cols(
        e1.extend(0.0),
        e2.extend(0.0),
        n.extend(0.0),
        centre.extend(1.0),
    ))
}

/// Two triangles covering the parallelogram of four points: a corner,
/// the half-edges from it, and the first triangle's normal.
fn triangles(p: &[DVec3], idx: &[usize]) -> Result<(DVec3, DVec3, DVec3, DVec3), String> {
    if idx.len() != 6 {
        return Err("only two triangles over four points are supported".into());
    }
    let tri_n = |k: usize| (p[idx[k + 1]] - p[idx[k]]).cross(p[idx[k + 2]] - p[idx[k]]);
    let (n0, n1) = (tri_n(0), tri_n(3));
    // The corner opposite point 0 is the one whose sum with it equals the
    // sum of the other two.
    let opp = (1..4).find(|&o| {
        let others: Vec<usize> = (1..4).filter(|&i| i != o).collect();
        ((p[0] + p[o]) - (p[others[0]] + p[others[1]])).length()
            <= 1e-6 * (p[o] - p[0]).length().max(1e-30)
    });
    let Some(o) = opp else {
        return Err("the four points are not a parallelogram".into());
    };
    let others: Vec<usize> = (1..4).filter(|&i| i != o).collect();
    let (e1, e2) = ((p[others[0]] - p[0]) / 2.0, (p[others[1]] - p[0]) / 2.0);
    let full = 4.0 * e1.cross(e2).length();
    if n0.dot(n1) <= 0.0 || ((n0.length() + n1.length()) / 2.0 - full).abs() > 1e-6 * full {
        return Err("the two triangles do not cover the parallelogram with one orientation".into());
    }
    Ok((p[0], e1, e2, n0))
}

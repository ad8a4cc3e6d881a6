//! Inline `trianglemesh` and `bilinearmesh` shapes that are not a single
//! parallelogram (those become fogbank's rectangle, see [`super::shapes`]):
//! written as a binary PLY file into a cache folder (the system's temporary
//! folder, `fogbank-pbrt-meshes`, named by a hash of the contents, so a
//! scene read again reuses it) and read by fogbank's `ply` shape.
//!
//! - `trianglemesh`: `P`, `indices` (optional for exactly three points),
//!   `N` and `uv` as given; without `N` the triangles are flat (pbrt's
//!   geometric normals), as `face_normals`. The front is pbrt's: the
//!   winding's normal (p₁ − p₀) × (p₂ − p₀). `faceIndices` only select
//!   ptex faces for textures (refused), so they are read and unused; `S`
//!   (shading tangents) is refused.
//! - `bilinearmesh`: `P`, `indices` (four per patch: p₀₀ p₁₀ p₀₁ p₁₁;
//!   optional for exactly four points), `N`, `uv`. A planar patch is
//!   exactly its two triangles (p₀₀ p₁₀ p₁₁, p₀₀ p₁₁ p₀₁), facing
//!   ∂p/∂u × ∂p/∂v as pbrt's; a curved one is tessellated into
//!   [`TESS`]×[`TESS`] quads of its bilinear surface, with a notice.
//!
//! Their area (for an area light's `power`) is the sum of the world-space
//! triangles'.

use super::params::ParamList;
use super::warnings::Warnings;
use glam::{DMat4, DVec2, DVec3};
use std::hash::{Hash, Hasher};
use std::path::PathBuf;

/// Quads along each side of a curved bilinear patch.
pub const TESS: usize = 8;

/// A triangle mesh in the shape's own space.
#[derive(Default)]
pub struct Mesh {
    pub p: Vec<DVec3>,
    pub n: Vec<DVec3>,
    pub uv: Vec<DVec2>,
    pub tris: Vec<[u32; 3]>,
}

impl Mesh {
    /// The area of the mesh under `m`.
    pub fn area(&self, m: DMat4) -> f64 {
        let q: Vec<DVec3> = self.p.iter().map(|&p| m.transform_point3(p)).collect();
        let tri = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| q[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        };
        self.tris.iter().map(tri).sum()
    }
}

fn vec3s(ps: &ParamList, ty: &str, name: &str) -> Option<Vec<DVec3>> {
    let v = ps.nums(ty, name)?;
    Some(
        v.chunks_exact(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect(),
    )
}

/// Points, normals and uvs.
type Vertices = (Vec<DVec3>, Vec<DVec3>, Vec<DVec2>);

/// `P`, `N` and `uv`, checked: every value finite, as many normals and
/// uvs as points.
fn vertices(ps: &ParamList) -> Result<Vertices, String> {
    let p = vec3s(ps, "point3", "P").ok_or("needs \"point3 P\"")?;
    let n = vec3s(ps, "normal", "N").unwrap_or_default();
    let uv: Vec<DVec2> = ps
        .nums("point2", "uv")
        .map(|v| v.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect())
        .unwrap_or_default();
    for (name, len, want) in [
        (
            "P",
            ps.nums("point3", "P").map_or(0, <[f64]>::len),
            3 * p.len(),
        ),
        ("N", n.len(), p.len()),
        ("uv", uv.len(), p.len()),
    ] {
        if name == "P" && len != want {
            return Err(format!("\"P\" has {len} values, not a multiple of 3"));
        }
        if name != "P" && len != 0 && len != want {
            return Err(format!("{len} values of \"{name}\" for {want} points"));
        }
    }
    let finite = p.iter().chain(&n).all(|v| v.is_finite()) && uv.iter().all(|v| v.is_finite());
    if !finite || p.is_empty() {
        return Err("needs finite \"P\" (and \"N\", \"uv\") values".into());
    }
    Ok((p, n, uv))
}

/// `indices`, `per` to an element, each below `points`; `default` when
/// absent and the points make exactly one element.
fn indices(ps: &ParamList, per: usize, points: usize) -> Result<Vec<u32>, String> {
    let idx: Vec<u32> = match ps.nums("integer", "indices") {
        Some(v) => v
            .iter()
            .map(|&i| {
                u32::try_from(i as i64)
                    .ok()
                    .filter(|&i| (i as usize) < points)
            })
            .collect::<Option<_>>()
            .ok_or(format!("an index is outside 0..{points}"))?,
        None if points == per => (0..per as u32).collect(),
        None => return Err("needs \"integer indices\"".into()),
    };
    if idx.is_empty() || !idx.len().is_multiple_of(per) {
        return Err(format!("{} indices, not a multiple of {per}", idx.len()));
    }
    Ok(idx)
}

/// A `trianglemesh` statement's mesh.
pub fn triangle_mesh(ps: &ParamList) -> Result<Mesh, String> {
    if ps.has("S") {
        return Err("shading tangents (\"S\") are not supported".into());
    }
    ps.nums("integer", "faceIndices");
    let (p, n, uv) = vertices(ps)?;
    let idx = indices(ps, 3, p.len())?;
    let tris = idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(Mesh { p, n, uv, tris })
}

/// A `bilinearmesh` statement's mesh.
pub fn bilinear_mesh(ps: &ParamList, warnings: &mut Warnings, loc: &str) -> Result<Mesh, String> {
    let (p, n, uv) = vertices(ps)?;
    let idx = indices(ps, 4, p.len())?;
    let mut out = Mesh::default();
    let mut curved = 0;
    for q in idx.chunks_exact(4) {
        let c = [q[0], q[1], q[2], q[3]].map(|i| i as usize);
        let [a, b, d, e] = c.map(|i| p[i]);
        let normal = (b - a).cross(d - a).normalize_or_zero();
        let planar = (e - a).dot(normal).abs() <= 1e-9 * (e - a).length();
        let k = if planar { 1 } else { TESS };
        curved += usize::from(!planar);
        let lerp4 = |v: [DVec3; 4], s: f64, t: f64| {
            (1.0 - s) * ((1.0 - t) * v[0] + t * v[2]) + s * ((1.0 - t) * v[1] + t * v[3])
        };
        let base = out.p.len() as u32;
        for j in 0..=k {
            for i in 0..=k {
                let (s, t) = (i as f64 / k as f64, j as f64 / k as f64);
                out.p.push(lerp4(c.map(|x| p[x]), s, t));
                if !n.is_empty() {
                    out.n.push(lerp4(c.map(|x| n[x]), s, t).normalize_or_zero());
                }
                if !uv.is_empty() {
                    let w = c.map(|x| uv[x].extend(0.0));
                    out.uv.push(lerp4(w, s, t).truncate());
                }
            }
        }
        let at = |i: usize, j: usize| base + (j * (k + 1) + i) as u32;
        for j in 0..k {
            for i in 0..k {
                out.tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                out.tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    if curved > 0 {
        warnings.warn(format!(
            "{loc}: bilinearmesh: {curved} curved patch(es) tessellated into {TESS}×{TESS} quads each (pbrt intersects the bilinear surface exactly)"
        ));
    }
    Ok(out)
}

/// Segments around an ellipsoid's equator (half as many pole to pole).
pub const ELLIPSOID_SEGMENTS: usize = 96;

/// The unit sphere under `m` as a world-space mesh with smooth normals
/// (the inverse transpose of `m` applied to the sphere's), its vertices
/// on the surface.
pub fn ellipsoid(m: DMat4) -> Mesh {
    let (nu, nv) = (ELLIPSOID_SEGMENTS, ELLIPSOID_SEGMENTS / 2);
    let normal_m = glam::DMat3::from_mat4(m).inverse().transpose();
    let mut out = Mesh::default();
    for j in 0..=nv {
        let theta = std::f64::consts::PI * j as f64 / nv as f64;
        for i in 0..=nu {
            let phi = 2.0 * std::f64::consts::PI * i as f64 / nu as f64;
            let d = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            out.p.push(m.transform_point3(d));
            out.n.push((normal_m * d).normalize_or_zero());
        }
    }
    let at = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    for j in 0..nv {
        for i in 0..nu {
            // Outward: (φ, θ) increasing is counter-clockwise seen from outside.
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if j > 0 {
                out.tris.push([a, c, b]);
            }
            if j + 1 < nv {
                out.tris.push([a, d, c]);
            }
        }
    }
    if glam::DMat3::from_mat4(m).determinant() < 0.0 {
        out.tris.iter_mut().for_each(|t| t.swap(1, 2));
    }
    out
}

/// The cached PLY file of `mesh`.
pub fn write_cached(mesh: &Mesh) -> Result<PathBuf, String> {
    let mut bytes = Vec::new();
    let (has_n, has_uv) = (!mesh.n.is_empty(), !mesh.uv.is_empty());
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
        mesh.p.len()
    );
    if has_n {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if has_uv {
        header += "property float u\nproperty float v\n";
    }
    header += &format!(
        "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.tris.len()
    );
    bytes.extend_from_slice(header.as_bytes());
    for (i, p) in mesh.p.iter().enumerate() {
        let mut v = p.to_array().to_vec();
        if has_n {
            v.extend(mesh.n[i].to_array());
        }
        if has_uv {
            v.extend(mesh.uv[i].to_array());
        }
        for x in v {
            bytes.extend_from_slice(&(x as f32).to_le_bytes());
        }
    }
    for t in &mesh.tris {
        bytes.push(3);
        for i in t {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
    }
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytes.hash(&mut h);
    let dir = std::env::temp_dir().join("fogbank-pbrt-meshes");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let out = dir.join(format!("{:016x}.ply", h.finish()));
    if !out.exists() {
        // Written beside and renamed, so a concurrent reader never sees half a file.
        let tmp = dir.join(format!("{:016x}.{}.tmp", h.finish(), std::process::id()));
        std::fs::write(&tmp, &bytes).map_err(|e| format!("{}: {e}", tmp.display()))?;
        std::fs::rename(&tmp, &out).map_err(|e| format!("{}: {e}", out.display()))?;
    }
    Ok(out)
}

//! PLY (ASCII, binary little- and big-endian) through `ply-rs-bw`, which
//! caps its preallocation whatever the header claims and reports the line
//! of ASCII errors. Reads `vertex` (`x y z`, optional `nx ny nz` and `u v`
//! / `s t` / `texture_u texture_v`) and `face` (`vertex_indices` or
//! `vertex_index`, polygons fan-triangulated).

use crate::mesh::TriangleMesh;
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{DefaultElement, Property};
use std::io::{BufReader, Read};
use std::path::Path;

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v as f64,
        Property::UChar(v) => v as f64,
        Property::Short(v) => v as f64,
        Property::UShort(v) => v as f64,
        Property::Int(v) => v as f64,
        Property::UInt(v) => v as f64,
        Property::Float(v) => v as f64,
        Property::Double(v) => v,
        _ => return None,
    })
}

/// A list of vertex indices; negative ones are refused by the caller
/// (they come back as `i64`).
fn list(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
        _ => return None,
    })
}

/// The first of `names` that `e` has, as f32.
fn get(e: &DefaultElement, names: &[&str]) -> Option<f32> {
    names
        .iter()
        .find_map(|n| e.get(*n).and_then(scalar))
        .map(|v| v as f32)
}

/// Parses PLY bytes; `what` names them in errors.
pub fn parse_ply(source: impl Read, what: &str) -> Result<TriangleMesh, String> {
    let parser = Parser::<DefaultElement>::new();
    let mut reader = Reader::new(BufReader::new(source));
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| format!("{what}: {e}"))?;
    // An element without properties occupies no bytes, so its count is
    // bounded by nothing in the file; the parser would still make that
    // many (empty) records.
    if let Some(e) = header
        .elements
        .values()
        .find(|e| e.count > 0 && e.properties.is_empty())
    {
        return Err(format!(
            "{what}: element `{}` declares {} entries but no properties",
            e.name, e.count
        ));
    }
    let payload = parser
        .read_payload(&mut reader, &header)
        .map_err(|e| format!("{what}: {e}"))?;
    let vertices = payload
        .get("vertex")
        .ok_or_else(|| format!("{what}: no `vertex` element"))?;
    let faces = payload
        .get("face")
        .ok_or_else(|| format!("{what}: no `face` element"))?;
    let mut positions = Vec::with_capacity(vertices.len());
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for (i, v) in vertices.iter().enumerate() {
        let c = |n: &str| get(v, &[n]).ok_or_else(|| format!("{what}: vertex {i} has no `{n}`"));
        positions.push(Vec3::new(c("x")?, c("y")?, c("z")?));
        if let (Some(x), Some(y), Some(z)) = (get(v, &["nx"]), get(v, &["ny"]), get(v, &["nz"])) {
            normals.push(Vec3::new(x, y, z));
        }
        if let (Some(s), Some(t)) = (
            get(v, &["u", "s", "texture_u", "texture_s"]),
            get(v, &["v", "t", "texture_v", "texture_t"]),
        ) {
            uvs.push(Vec2::new(s, t));
        }
    }
    if normals.len() != positions.len() {
        normals.clear();
    }
    if uvs.len() != positions.len() {
        uvs.clear();
    }
    let mut triangles = Vec::with_capacity(faces.len());
    for (i, f) in faces.iter().enumerate() {
        let idx = ["vertex_indices", "vertex_index"]
            .iter()
            .find_map(|n| f.get(*n).and_then(list))
            .ok_or_else(|| format!("{what}: face {i} has no `vertex_indices` list"))?;
        if idx.len() < 3 {
            return Err(format!("{what}: face {i} has {} vertices", idx.len()));
        }
        let n = positions.len() as i64;
        if let Some(bad) = idx.iter().find(|&&k| k < 0 || k >= n) {
            return Err(format!("{what}: face {i} names vertex {bad} of {n}"));
        }
        for k in 1..idx.len() - 1 {
            triangles.push([idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
        }
    }
    if triangles.is_empty() {
        return Err(format!("{what}: no faces"));
    }
    TriangleMesh::new(what, positions, triangles, normals, uvs)
}

pub fn load(path: &Path) -> Result<TriangleMesh, String> {
    let what = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| format!("{what}: {e}"))?;
    parse_ply(std::io::BufReader::new(file), &what)
}

#[cfg(test)]
mod ply_test {
    use super::*;

    const ASCII: &str =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                         property float z\nproperty float u\nproperty float v\nelement face 1\n\
                         property list uchar int vertex_indices\nend_header\n\
                         0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n";

    fn binary_le() -> Vec<u8> {
        let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                      property float y\nproperty float z\nelement face 1\n\
                      property list uchar uint vertex_indices\nend_header\n"
            .to_vec();
        for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for c in p {
                b.extend(c.to_le_bytes());
            }
        }
        b.push(3);
        for i in 0u32..3 {
            b.extend(i.to_le_bytes());
        }
        b
    }

    #[test]
    fn ascii_quad_and_binary_triangle() {
        let m = parse_ply(ASCII.as_bytes(), "quad.ply").unwrap();
        assert_eq!((m.len(), m.uvs.len(), m.normals.len()), (2, 4, 0));
        let m = parse_ply(&binary_le()[..], "tri.ply").unwrap();
        assert_eq!(m.len(), 1);
        assert_eq!(m.positions[1], Vec3::X);
    }

    #[test]
    fn malformed_files_are_refused_by_name() {
        let e = parse_ply(ASCII.replace("1 1 0 1 1", "1 x 0 1 1").as_bytes(), "q.ply").unwrap_err();
        assert!(e.starts_with("q.ply: ") && e.contains("Line"), "{e}");
        let e = parse_ply(ASCII.replace("4 0 1 2 3", "4 0 1 2 7").as_bytes(), "q.ply").unwrap_err();
        assert!(e.contains("face 0 names vertex 7 of 4"), "{e}");
        // A header claiming 10⁹ vertices over a few bytes: an error, not an
        // allocation of gigabytes.
        let mut huge = binary_le();
        let at = huge.windows(9).position(|w| w == b"vertex 3\n").unwrap();
        huge.splice(at..at + 9, b"vertex 1000000000\n".iter().copied());
        assert!(parse_ply(&huge[..], "huge.ply").is_err());
        // Truncated binary data.
        let b = binary_le();
        assert!(parse_ply(&b[..b.len() - 3], "cut.ply").is_err());
        // 22 million faces without properties in 581 bytes (found by the
        // `ply` fuzz target: gigabytes of empty records before the check).
        let bytes = include_bytes!("../../tests/fixtures/fuzz/ply_propertyless_faces.ply");
        let e = parse_ply(&bytes[..], "empty.ply").unwrap_err();
        assert!(
            e.contains("`face` declares 22401047 entries but no properties"),
            "{e}"
        );
    }
}

//! Wavefront OBJ through `tobj` (polygons fan-triangulated, one index per
//! vertex; every object and group merged into one mesh; materials ignored:
//! fogbank's scene gives the BSDF). `tobj` reports what went wrong but not
//! where; the line is found by parsing growing prefixes of the file (a
//! prefix fails once it contains the faulty line), only on the error path.

use crate::mesh::TriangleMesh;
use glam::{Vec2, Vec3};
use std::path::Path;

fn options() -> tobj::LoadOptions {
    tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    }
}

fn parse(text: &str) -> Result<Vec<tobj::Model>, tobj::LoadError> {
    let mut reader = std::io::BufReader::new(text.as_bytes());
    tobj::load_obj_buf(&mut reader, &options(), |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map(|(models, _)| models)
}

/// The 1-based line whose inclusion first makes the file fail to parse.
fn faulty_line(text: &str) -> usize {
    let ends: Vec<usize> = text
        .char_indices()
        .filter(|&(_, c)| c == '\n')
        .map(|(i, _)| i + 1)
        .chain(std::iter::once(text.len()))
        .collect();
    let (mut ok, mut bad) = (0usize, ends.len());
    while bad - ok > 1 {
        let mid = (ok + bad) / 2;
        if parse(&text[..ends[mid - 1]]).is_err() {
            bad = mid;
        } else {
            ok = mid;
        }
    }
    bad
}

/// Checks every face's vertex, texture-coordinate and normal references
/// against what the file has defined before it (1-based, or negative and
/// relative). `tobj` 4.0.5 multiplies unchecked indices (a relative
/// texture index before the first `vt` overflows), so references are
/// checked here first; errors name the line.
fn check_references(text: &str, what: &str) -> Result<(), String> {
    let mut counts = [0i64; 3]; // v, vt, vn
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") if !line.trim_end().ends_with('\\') => {
                for word in words {
                    for (k, part) in word.split('/').enumerate().take(3) {
                        if part.is_empty() {
                            continue;
                        }
                        let kind = ["vertex", "texture coordinate", "normal"][k];
                        let bad = || {
                            format!(
                                "{what}:{}: face refers to {kind} {part} of {}",
                                i + 1,
                                counts[k]
                            )
                        };
                        let Ok(idx) = part.parse::<i64>() else {
                            // Not a number: tobj reports it (with our line).
                            continue;
                        };
                        if idx == 0 || idx > counts[k] || idx < -counts[k] {
                            return Err(bad());
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Parses OBJ text; `what` names it in errors.
pub fn parse_obj(text: &str, what: &str) -> Result<TriangleMesh, String> {
    check_references(text, what)?;
    let models = parse(text).map_err(|e| format!("{what}:{}: {e}", faulty_line(text)))?;
    let (mut positions, mut triangles, mut normals, mut uvs) = (vec![], vec![], vec![], vec![]);
    let (mut all_normals, mut all_uvs) = (true, true);
    for m in &models {
        let mesh = &m.mesh;
        let base = positions.len() as u32;
        let n = mesh.positions.len() / 3;
        positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        triangles.extend(
            mesh.indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
        all_normals &= mesh.normals.len() == 3 * n;
        all_uvs &= mesh.texcoords.len() == 2 * n;
        normals.extend(
            mesh.normals
                .chunks_exact(3)
                .map(|v| Vec3::new(v[0], v[1], v[2])),
        );
        uvs.extend(
            mesh.texcoords
                .chunks_exact(2)
                .map(|v| Vec2::new(v[0], v[1])),
        );
    }
    // Attributes only when every object has them.
    if !all_normals {
        normals.clear();
    }
    if !all_uvs {
        uvs.clear();
    }
    if triangles.is_empty() {
        return Err(format!("{what}: no faces"));
    }
    TriangleMesh::new(what, positions, triangles, normals, uvs)
}

pub fn load(path: &Path) -> Result<TriangleMesh, String> {
    let what = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{what}: {e}"))?;
    parse_obj(&text, &what)
}

#[cfg(test)]
mod obj_test {
    use super::*;

    const QUAD: &str =
        "# a unit quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                        vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";

    #[test]
    fn quad_is_two_triangles_with_attributes() {
        let m = parse_obj(QUAD, "quad.obj").unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!(m.normals.len(), m.positions.len());
        assert_eq!(m.uvs.len(), m.positions.len());
        assert!(m.normals.iter().all(|n| *n == Vec3::Z));
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let bad = QUAD.replace("v 1 1 0", "v 1 x 0");
        let e = parse_obj(&bad, "quad.obj").unwrap_err();
        assert!(e.starts_with("quad.obj:4: "), "{e}");
        let oob = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n";
        let e = parse_obj(oob, "oob.obj").unwrap_err();
        assert!(e.starts_with("oob.obj:5: "), "{e}");
        // A relative texture index before any `vt` (tobj 4.0.5 overflowed on
        // it; found by the fuzzer).
        let rel = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/-91 2 3\n";
        let e = parse_obj(rel, "rel.obj").unwrap_err();
        assert!(
            e.starts_with("rel.obj:4: ") && e.contains("texture coordinate -91 of 0"),
            "{e}"
        );
        let fuzz = "0 0 0\nv 1 0 0\n 1\n 1 01\nf 1/-91 2/ 0\nvt 1 1\nvt 0 1\nvn 01 1/2/1 4 7/4/1\n";
        assert!(parse_obj(fuzz, "fuzz.obj").is_err());
        let e = parse_obj("v 0 0 0\n", "points.obj").unwrap_err();
        assert!(e.contains("no faces"), "{e}");
    }
}

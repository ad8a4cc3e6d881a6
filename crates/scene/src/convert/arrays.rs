//! In-memory arrays in a converted scene: pbrt-v4's `uniformgrid` media
//! (and Python's `fogbank.Grid`s) are registered in the converting process
//! only (`density = { array = "array:3" }`), so a written scene names them
//! as `.vol` files beside it instead (`STEM_arrayN.vol`, every channel,
//! placed on the array's box), which load with the same values there.

use fogbank_render::error::SceneError;
use fogbank_render::world::arrays;
use fogbank_volume::loaders::vol::write_vol;
use std::collections::HashMap;
use std::path::Path;
use toml::Value;

/// Writes each array `doc` names to `dir` as `STEM_arrayN.vol` and names
/// that file instead (relative: the scene is written to `dir`).
pub fn write_arrays(doc: &mut Value, dir: &Path, stem: &str) -> Result<(), SceneError> {
    let mut written = HashMap::new();
    walk(doc, dir, stem, "", &mut written)
}

fn walk(
    v: &mut Value,
    dir: &Path,
    stem: &str,
    key: &str,
    written: &mut HashMap<String, String>,
) -> Result<(), SceneError> {
    match v {
        Value::Table(t) => {
            if let Some(Value::String(name)) = t.get("array").cloned() {
                let file = match written.get(&name) {
                    Some(f) => f.clone(),
                    None => {
                        let f = format!("{stem}_array{}.vol", written.len());
                        write_array(&name, key, &dir.join(&f))?;
                        written.insert(name, f.clone());
                        f
                    }
                };
                t.remove("array");
                t.insert("vol".into(), Value::String(file));
            }
            for (k, x) in t.iter_mut() {
                walk(x, dir, stem, &join(key, k), written)?;
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter_mut().enumerate() {
                walk(x, dir, stem, &join(key, &i.to_string()), written)?;
            }
        }
        _ => {}
    }
    Ok(())
}

fn join(key: &str, k: &str) -> String {
    if key.is_empty() {
        k.to_string()
    } else {
        format!("{key}.{k}")
    }
}

/// The array `name` (of scene key `key`) as the `.vol` file `path`: its
/// values x fastest, channels interleaved, on the box its index→world map
/// spans (which must be a scale and translation, as a `.vol`'s is).
fn write_array(name: &str, key: &str, path: &Path) -> Result<(), SceneError> {
    let a = arrays::get(name, key)?;
    let m = a.index_to_world();
    let d = glam::DVec3::new(m.matrix3.x_axis.x, m.matrix3.y_axis.y, m.matrix3.z_axis.z);
    let diagonal = m.matrix3 == glam::DMat3::from_diagonal(d);
    if !diagonal {
        return Err(SceneError(format!(
            "{key}.array: a rotated array has no .vol to hold it (a .vol is placed on an axis-aligned box)"
        )));
    }
    let [nx, ny, nz] = a.dims();
    let lo = m.transform_point3(glam::DVec3::ZERO).as_vec3();
    let hi = m
        .transform_point3(glam::DVec3::new(nx as f64, ny as f64, nz as f64))
        .as_vec3();
    let c = a.channels();
    let mut values = Vec::with_capacity((nx * ny * nz * c) as usize);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                values.extend((0..c).map(|ch| a.value(i, j, k, ch)));
            }
        }
    }
    let bbox = [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z];
    write_vol(path, [nx, ny, nz], c, bbox, &values)
        .map_err(|e| SceneError(format!("{}: {e}", path.display())))
}

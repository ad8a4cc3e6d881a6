//! Inline voxel grids (the arrays of `uniformgrid` and `rgbgrid` media,
//! and the grid a `cloud` medium is baked into) as
//! fogbank's in-memory arrays ([`fogbank_render::world::arrays`]): the scene
//! description names them, and this module owns them for the rest of the
//! process, since the description outlives the reading. An identical grid
//! read again (a viewer reloading the scene) is the same array, so
//! re-reading an unchanged file holds no more memory. A grid medium's
//! resolution and box parameters are read here too ([`grid_box`]).

use super::params::ParamList;
use fogbank_math::{DAffine3, DVec3};
use fogbank_render::world::arrays;
use fogbank_volume::{DenseArray, VoxelArray};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

/// An owned array and the name it is registered under.
type Owned = (Arc<dyn VoxelArray>, String);

/// Arrays by a hash of their contents and placement.
static OWNED: Mutex<Option<HashMap<u64, Owned>>> = Mutex::new(None);

/// Registers the `n[0]·n[1]·n[2]` voxels of `channels` (1 or 3) values
/// each (x fastest, as pbrt orders them; channel fastest within a voxel)
/// spanning the box `p0`–`p1` cell-centred (pbrt's `SampledGrid::Lookup`
/// at (p − p0)/(p1 − p0)·n − ½); returns the name a field gives as
/// `array`.
pub fn register(
    n: [u32; 3],
    channels: u32,
    values: &[f64],
    p0: DVec3,
    p1: DVec3,
    source: &str,
) -> Result<String, String> {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    n.hash(&mut h);
    channels.hash(&mut h);
    for v in values
        .iter()
        .chain(p0.to_array().iter())
        .chain(p1.to_array().iter())
    {
        v.to_bits().hash(&mut h);
    }
    let key = h.finish();
    let mut owned = OWNED.lock().unwrap_or_else(|e| e.into_inner());
    let owned = owned.get_or_insert_with(HashMap::new);
    let size = (p1 - p0) / DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
    let xf = DAffine3::from_translation(p0) * DAffine3::from_scale(size);
    if let Some((a, name)) = owned.get(&key) {
        if same(a.as_ref(), n, channels, values, xf) {
            return Ok(name.clone());
        }
    }
    let data = values.iter().map(|&v| v as f32).collect();
    let a =
        DenseArray::new(n, channels, data, xf, source.to_string()).map_err(|e| e.to_string())?;
    let a: Arc<dyn VoxelArray> = Arc::new(a);
    let name = arrays::register(&a);
    owned.insert(key, (a, name.clone()));
    Ok(name)
}

/// Whether `a` holds exactly these values so placed (a hash is not proof).
fn same(a: &dyn VoxelArray, n: [u32; 3], channels: u32, values: &[f64], xf: DAffine3) -> bool {
    let count = n.iter().map(|&v| v as usize).product::<usize>() * channels as usize;
    if a.dims() != n
        || a.channels() != channels
        || a.index_to_world() != xf
        || values.len() != count
    {
        return false;
    }
    let mut i = 0;
    for z in 0..n[2] {
        for y in 0..n[1] {
            for x in 0..n[0] {
                for c in 0..channels {
                    if a.value(x, y, z, c) != values[i] as f32 {
                        return false;
                    }
                    i += 1;
                }
            }
        }
    }
    true
}

/// A grid medium's `nx`, `ny`, `nz` (1) and box `p0`–`p1` (0–1).
pub fn grid_box(ps: &ParamList) -> Result<([u32; 3], DVec3, DVec3), String> {
    let mut n = [1u32; 3];
    for (i, k) in ["nx", "ny", "nz"].iter().enumerate() {
        let v = ps.int(k, 1).map_err(|e| e.0)?;
        n[i] = u32::try_from(v)
            .ok()
            .filter(|&v| (1..=4096).contains(&v))
            .ok_or(format!("{k} = {v} outside 1..=4096"))?;
    }
    let point = |k: &str, default: DVec3| -> Result<DVec3, String> {
        Ok(ps
            .vec3(k)
            .map_err(|e| e.0)?
            .map(DVec3::from)
            .unwrap_or(default))
    };
    let (p0, p1) = (point("p0", DVec3::ZERO)?, point("p1", DVec3::ONE)?);
    if !(p1 - p0).cmpgt(DVec3::ZERO).all() {
        return Err("needs p0 < p1 on every axis".into());
    }
    Ok((n, p0, p1))
}

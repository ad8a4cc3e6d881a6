//! Public entry points: listing a file's grids from its segment headers,
//! choosing one by name, decoding its buffer and flattening its tree into
//! [`VdbGrid`]s.

use std::path::Path;

use super::checksum;
use super::codec::decode;
use super::gridbuf::GridBuf;
use super::griddata::parse_head;
use super::layout::{type_name, ValueKind};
use super::segment::{parse_entries, version_string, Codec, GridEntry, Source};
use super::tree::{read_tree, Flat};
use crate::error::{Result, VolumeError};
use crate::loaders::grid_choice::{pick_default, ListedGrid};
use crate::loaders::vdb::{GridClass, VdbGrid, VdbGridDescriptor, VdbLeaf};

/// Lists the grids of a file with their types, reading only the headers.
pub fn list_grids(path: &Path) -> Result<Vec<VdbGridDescriptor>> {
    let mut src = open(path)?;
    Ok(parse_entries(path, &mut src)?
        .iter()
        .map(describe)
        .collect())
}

/// [`list_grids`] on bytes already in memory; `path` only names the source
/// in error messages.
pub fn list_grids_from_bytes(path: &Path, bytes: &[u8]) -> Result<Vec<VdbGridDescriptor>> {
    let mut src = Source::Bytes(bytes);
    Ok(parse_entries(path, &mut src)?
        .iter()
        .map(describe)
        .collect())
}

/// Reads one float grid (full precision, double or quantised). `name =
/// None` picks `density`, else the first float grid.
pub fn read_grid(path: &Path, name: Option<&str>) -> Result<VdbGrid> {
    let [g] = read_k::<1>(path, &mut open(path)?, name)?;
    Ok(g)
}

/// Same as [`read_grid`] from bytes already in memory (used by the fuzz
/// target). `path` is only used in messages.
pub fn read_grid_from_bytes(path: &Path, bytes: &[u8], name: Option<&str>) -> Result<VdbGrid> {
    let [g] = read_k::<1>(path, &mut Source::Bytes(bytes), name)?;
    Ok(g)
}

/// Reads one `Vec3f` or `Vec3d` grid (velocity) as its x, y and z
/// components: three float grids named `name.x`, `name.y`, `name.z` with
/// the same topology, transform and class. `name = None` picks a vector
/// grid named `vel`, `v` or `velocity` (in that order of preference), else
/// the first vector grid.
pub fn read_vec3_grid(path: &Path, name: Option<&str>) -> Result<[VdbGrid; 3]> {
    read_k::<3>(path, &mut open(path)?, name)
}

/// Same as [`read_vec3_grid`] from bytes already in memory (used by the
/// fuzz target). `path` is only used in messages.
pub fn read_vec3_grid_from_bytes(
    path: &Path,
    bytes: &[u8],
    name: Option<&str>,
) -> Result<[VdbGrid; 3]> {
    read_k::<3>(path, &mut Source::Bytes(bytes), name)
}

fn open(path: &Path) -> Result<Source<'static>> {
    let file = std::fs::File::open(path).map_err(|e| VolumeError::io(path, e))?;
    let len = file.metadata().map_err(|e| VolumeError::io(path, e))?.len();
    Ok(Source::File(file, len))
}

fn kind(e: &GridEntry) -> Option<ValueKind> {
    ValueKind::from_grid_type(e.grid_type)
}

fn grid_class(c: u32) -> GridClass {
    match c {
        1 => GridClass::LevelSet,
        2 => GridClass::FogVolume,
        3 => GridClass::Staggered,
        _ => GridClass::Unknown,
    }
}

fn describe(e: &GridEntry) -> VdbGridDescriptor {
    VdbGridDescriptor {
        name: e.name.clone(),
        value_type: type_name(e.grid_type).to_string(),
        grid_class: grid_class(e.grid_class),
        stored_as_half: false,
        supported: kind(e).is_some_and(|k| k.components() == 1),
    }
}

fn read_k<const K: usize>(
    path: &Path,
    src: &mut Source,
    name: Option<&str>,
) -> Result<[VdbGrid; K]> {
    let entries = parse_entries(path, src)?;
    let e = select(path, &entries, name, K)?;
    let stored = src.read(path, e.data_pos, usize_len(path, e)?)?;
    let bytes = decode(path, e, stored)?;
    let b = GridBuf {
        data: &bytes,
        path,
        grid: &e.name,
        file_pos: (e.codec == Codec::None).then_some(e.data_pos),
    };
    let head = parse_head(&b)?;
    if kind(e) != Some(head.kind) {
        return Err(b.fail(
            636,
            format!(
                "grid type differs from the {} its segment metadata declares",
                type_name(e.grid_type)
            ),
        ));
    }
    let flat = read_tree::<K>(&b, &head)?;
    checksum::verify(&b, &head, &flat)?;
    // The decoded grid is no longer needed: free it before the leaves are
    // split into grids (peak memory while loading).
    drop(bytes);
    let mut compression = e.codec.name().to_string();
    if head.kind.is_quantised() {
        compression = format!("{} + {}", type_name(e.grid_type), compression);
    }
    Ok(split(flat, |c| VdbGrid {
        name: match K {
            1 => e.name.clone(),
            _ => format!("{}.{}", e.name, ["x", "y", "z"][c]),
        },
        grid_class: grid_class(head.grid_class),
        file_version: head.version,
        stored_as_half: false,
        compression: compression.clone(),
        background: 0.0,
        index_to_world: head.index_to_world,
        leaves: Vec::new(),
        tiles: Vec::new(),
    }))
}

fn usize_len(path: &Path, e: &GridEntry) -> Result<usize> {
    usize::try_from(e.file_size)
        .map_err(|_| VolumeError::format(path, format!("grid `{}` is too large to read", e.name)))
}

/// One float grid per component of `flat`, each made by `base` and given
/// its component's background, leaves and tiles. `flat` is consumed leaf
/// by leaf, so its values and the grids' never need memory at once beyond
/// one leaf.
fn split<const K: usize>(flat: Flat<K>, base: impl Fn(usize) -> VdbGrid) -> [VdbGrid; K] {
    let mut grids: [VdbGrid; K] = std::array::from_fn(|c| {
        let mut g = base(c);
        g.background = flat.background[c];
        g.tiles = flat.tiles.iter().map(|t| t.component(c)).collect();
        g.leaves = Vec::with_capacity(flat.leaves.len());
        g
    });
    for l in flat.leaves {
        for (c, g) in grids.iter_mut().enumerate() {
            let mut values = Box::new([0.0f32; 512]);
            for (v, &src) in values.iter_mut().zip(l.values.iter().skip(c).step_by(K)) {
                *v = src;
            }
            g.leaves.push(VdbLeaf {
                origin: l.origin,
                values,
                active: l.active,
            });
        }
    }
    grids
}

impl ListedGrid for GridEntry {
    fn grid_name(&self) -> &str {
        &self.name
    }

    fn describe(&self) -> String {
        format!("`{}` ({})", self.name, type_name(self.grid_type))
    }
}

/// Picks the grid to read: by name, else by the default names, else the
/// first grid with `k` components. A named grid of another type is an
/// error that names its type.
fn select<'e>(
    path: &Path,
    entries: &'e [GridEntry],
    name: Option<&str>,
    k: usize,
) -> Result<&'e GridEntry> {
    let wanted = if k == 3 {
        "Vec3f or Vec3d (velocity)"
    } else {
        "float (float, double, Fp4, Fp8, Fp16 or FpN)"
    };
    let fits = |e: &GridEntry| kind(e).is_some_and(|kind| kind.components() == k);
    let Some(name) = name else {
        return pick_default(path, entries, k, fits, wanted);
    };
    let Some(e) = entries.iter().find(|e| e.name == name) else {
        return Err(VolumeError::GridNotFound {
            path: path.to_path_buf(),
            grid: name.to_string(),
            available: entries.iter().map(|e| e.name.clone()).collect(),
        });
    };
    if fits(e) {
        return Ok(e);
    }
    Err(VolumeError::format(
        path,
        format!(
            "grid `{}` has value type {} (NanoVDB {}); only {wanted} grids can be read here{}",
            e.name,
            type_name(e.grid_type),
            version_string(e.version),
            match kind(e).map(|kind| kind.components()) {
                Some(3) => "; vector grids are read as three components by read_vec3_grid",
                Some(_) => "; float grids are read by read_grid",
                None => "",
            }
        ),
    ))
}

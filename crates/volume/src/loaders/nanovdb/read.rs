//! Public entry points: listing a file's grids from its segment headers,
//! choosing one by name, decoding its buffer and flattening its tree into
//! [`VdbGrid`]s.

use std::path::Path;

use fogbank_math::DAffine3;

use super::checksum;
use super::gridbuf::GridBuf;
use super::griddata::{parse_head, GridHead, HEAD_LEN};
use super::layout::{type_name, Layout, ValueKind};
use super::leaves::{stream_leaves, LeafValues};
use super::segment::{parse_entries, version_string, Codec, GridEntry, Source};
use super::stream::GridStream;
use super::tree::{read_tree, Flat};
use crate::error::{Result, VolumeError};
use crate::grid::{BrickGrid, Voxel};
use crate::grid_builder::convert_brick;
use crate::leaf_bricks::LeafBricks;
use crate::loaders::grid_choice::{pick_default, ListedGrid};
use crate::loaders::vdb::{GridClass, VdbGrid, VdbGridDescriptor, VdbLeaf};
use crate::loaders::vdb_grid::{self, brick_order};

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

/// A grid whose internal nodes are read (`prefix`, the buffer up to its
/// first leaf) and whose leaves are still to stream past.
struct Opened<'a, const K: usize> {
    stream: GridStream<'a>,
    prefix: Vec<u8>,
    head: GridHead,
    flat: Flat<K>,
    entry: &'a GridEntry,
    path: &'a Path,
}

/// The bounds-checked view of `prefix`, the first bytes of `e`'s buffer
/// of `size` bytes.
fn grid_buf<'b>(prefix: &'b [u8], size: usize, path: &'b Path, e: &'b GridEntry) -> GridBuf<'b> {
    GridBuf {
        data: prefix,
        base: 0,
        total: size,
        path,
        grid: &e.name,
        stored: match e.codec {
            Codec::None => Ok(e.data_pos),
            Codec::Zip => Err("ZIP"),
            Codec::Blosc => Err("BLOSC"),
        },
    }
}

impl<const K: usize> Opened<'_, K> {
    /// The grid as the reader gives it, without its leaves.
    fn outline(&self) -> VdbGrid {
        let (e, head) = (self.entry, &self.head);
        let mut compression = e.codec.name().to_string();
        if head.kind.is_quantised() {
            compression = format!("{} + {}", type_name(e.grid_type), compression);
        }
        VdbGrid {
            name: e.name.clone(),
            grid_class: grid_class(head.grid_class),
            file_version: head.version,
            stored_as_half: false,
            compression,
            background: self.flat.background[0],
            index_to_world: head.index_to_world,
            leaves: Vec::new(),
            tiles: self.flat.tiles.iter().map(|t| t.component(0)).collect(),
        }
    }

    /// Streams the leaves through `make` (in parallel) and `keep` (in
    /// buffer order), then checks the end of the data and the checksum.
    fn read_leaves<R: Send>(
        self,
        make: impl Fn(usize, LeafValues) -> R + Sync,
        keep: impl FnMut(usize, R) -> Result<()>,
    ) -> Result<()> {
        let Opened {
            mut stream,
            prefix,
            head,
            flat,
            entry,
            path,
        } = self;
        let b = grid_buf(&prefix, stream.size(), path, entry);
        let lay = Layout::new(head.kind);
        let mut crcs = checksum::applies(&head).then(Vec::new);
        stream_leaves::<K, R>(
            &mut stream,
            &b,
            &lay,
            &flat.leaves,
            crcs.as_mut(),
            make,
            keep,
        )?;
        stream.finish()?;
        checksum::verify(&b, &head, &flat, &crcs.unwrap_or_default())
    }
}

/// Reads the grid `e` up to its leaves: header, internal nodes, tiles and
/// where each leaf lies.
fn open_grid<'a, const K: usize>(
    path: &'a Path,
    src: &'a mut Source,
    e: &'a GridEntry,
) -> Result<Opened<'a, K>> {
    let mut stream = GridStream::open(path, src, e)?;
    let size = stream.size();
    let mut prefix = Vec::new();
    stream.read_into(&mut prefix, HEAD_LEN.min(size))?;
    let head = parse_head(&grid_buf(&prefix, size, path, e))?;
    // NanoVDB puts every internal node in front of the leaves.
    let first_leaf = match head.node_count[0] {
        0 => size,
        _ => head.node_offset[0],
    };
    let more = first_leaf.saturating_sub(prefix.len());
    stream.read_into(&mut prefix, more)?;
    let b = grid_buf(&prefix, size, path, e);
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
    Ok(Opened {
        stream,
        prefix,
        head,
        flat,
        entry: e,
        path,
    })
}

fn read_k<const K: usize>(
    path: &Path,
    src: &mut Source,
    name: Option<&str>,
) -> Result<[VdbGrid; K]> {
    let entries = parse_entries(path, src)?;
    let e = select(path, &entries, name, K)?;
    let o = open_grid::<K>(path, src, e)?;
    let base = o.outline();
    let mut grids: [VdbGrid; K] = std::array::from_fn(|c| {
        let mut g = base.clone();
        if K > 1 {
            g.name = format!("{}.{}", e.name, ["x", "y", "z"][c]);
        }
        g.background = o.flat.background[c];
        g.tiles = o.flat.tiles.iter().map(|t| t.component(c)).collect();
        g
    });
    let mut leaves: Vec<Option<LeafValues>> = Vec::new();
    leaves.resize_with(o.flat.leaves.len(), || None);
    o.read_leaves(
        |_, l| l,
        |index, l| {
            leaves[index] = Some(l);
            Ok(())
        },
    )?;
    // In the walk's order, each leaf split into its components.
    for l in leaves.into_iter().flatten() {
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
    Ok(grids)
}

/// Reads one float grid (as [`read_grid`]) straight into fogbank's brick
/// grid in precision `T`, each value mapped by the map that `choose`
/// picks for the grid (given it without its leaves): what
/// [`vdb_grid::to_builder`] and `finish_converted` make of [`read_grid`]'s
/// grid, bit for bit, but the leaves stream from the file into their
/// bricks, so loading costs little more memory than the grid it makes.
/// Returns the grid, its index→world map and the grid without its leaves.
pub fn read_grid_bricks<T: Voxel, F: Fn(f32) -> f32 + Sync>(
    path: &Path,
    name: Option<&str>,
    choose: impl FnOnce(&VdbGrid) -> F,
) -> Result<(BrickGrid<T>, DAffine3, VdbGrid)> {
    let mut src = open(path)?;
    let entries = parse_entries(path, &mut src)?;
    let e = select(path, &entries, name, 1)?;
    let o = open_grid::<1>(path, &mut src, e)?;
    let outline = o.outline();
    let f = choose(&outline);
    let origins = o.flat.leaves.iter().map(|l| l.origin);
    let (builder, origin, xf) = vdb_grid::outline_builder(&outline, origins)?;
    // Every leaf origin lies on the brick lattice inside the grid (the grid
    // is its leaves' and tiles' box, padded, on that lattice).
    let bricks: Vec<usize> = o
        .flat
        .leaves
        .iter()
        .map(|l| builder.aligned_brick(vdb_grid::leaf_lo(l.origin, origin)))
        .collect::<Option<_>>()
        .ok_or_else(|| {
            VolumeError::Invalid(format!(
                "grid `{}` has a leaf off the brick lattice",
                e.name
            ))
        })?;
    let mut out = LeafBricks::<T>::new(builder, &bricks);
    let (dims, bdims) = out.dims();
    o.read_leaves(
        |index, l| {
            let mut values = [0.0f32; 512];
            values.copy_from_slice(&l.values);
            brick_order(&mut values);
            convert_brick::<T>(bricks[index], dims, bdims, Some(&values), 0.0, &f)
        },
        |index, content| {
            out.put(bricks[index], content);
            Ok(())
        },
    )?;
    Ok((out.finish(&f), xf, outline))
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

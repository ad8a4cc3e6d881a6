//! OpenVDB (`.vdb`) reader for float grids.
//!
//! Our own parser rather than a binding or the `vdb-rs` crate: that crate
//! aborts on half-float compressed grids and rejects affine transforms, and
//! a renderer must survive whatever file a user hands it. Every count and
//! size read from the file is checked against the bytes that remain before
//! anything is allocated, and decompressed sizes are capped by what the node
//! needs, so malformed input yields a [`VolumeError`] naming the file, the
//! grid and the byte offset, never a panic or a huge allocation.
//!
//! | feature | supported |
//! |---|---|
//! | file format versions | 222 – 225 (224 is what Houdini 17+ and OpenVDB 6 – 11 write); older and newer versions are rejected with a clear error |
//! | grid value types | `float` with the standard 5-4-3 tree; other types are listed (`supported = false`) and skipped |
//! | storage | float32, half float (`_HalfFloat` grids) |
//! | compression | none, Zip (zlib), Blosc (blosclz, lz4, lz4hc, zlib codecs; byte and bit shuffle), active-mask (all 7 per-node modes) |
//! | Blosc codecs snappy, zstd | no (clear error) |
//! | transforms | UniformScale, UniformScaleTranslate, Scale, ScaleTranslate, Translation, Affine, Unitary maps; frustum and other non-linear maps are rejected |
//! | tree | root, internal (32³, 16³) and leaf nodes; constant tiles at every level, active or inactive |
//! | several grids per file | yes; selected by name (`name`, or `name[N]` for duplicated names) using the stored grid offsets |
//! | instanced grids | yes (the tree is read from the instance parent) |
//! | files without grid offsets (streams) | yes, as long as every grid before the wanted one is a float grid |
//! | large files | read whole up to 64 MiB; beyond that only the header, the descriptors and the chosen grid's bytes are read |
//! | delayed-load metadata, multi-pass (point) grids | ignored / not supported |

pub mod blosc;

use std::path::Path;

use crate::error::{Result, VolumeError};

/// The oldest format that stores compression per grid and per-node mask
/// metadata; older files would need a second, rarely exercised code path.
const MIN_FILE_VERSION: u32 = 222;
/// The newest format we know (OpenVDB 12 added native half grids, which we
/// list as unsupported but otherwise read like 224).
const MAX_FILE_VERSION: u32 = 225;

const COMPRESS_ZIP: u32 = 0x1;
const COMPRESS_ACTIVE_MASK: u32 = 0x2;
const COMPRESS_BLOSC: u32 = 0x4;

const MAGIC: [u8; 8] = [0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0];
const HALF_SUFFIX: &str = "_HalfFloat";
const NAME_SEP: char = '\x1e';
const FLOAT_TREE: &str = "Tree_float_5_4_3";

/// How OpenVDB classifies a grid; renderers treat fog volumes as density and
/// level sets as signed distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridClass {
    FogVolume,
    LevelSet,
    Staggered,
    Unknown,
}

impl GridClass {
    fn from_meta(s: &str) -> GridClass {
        match s {
            "fog volume" => GridClass::FogVolume,
            "level set" => GridClass::LevelSet,
            "staggered" => GridClass::Staggered,
            _ => GridClass::Unknown,
        }
    }
}

/// What `list_grids` reports per grid, enough to pick one without reading it.
#[derive(Debug, Clone, PartialEq)]
pub struct VdbGridDescriptor {
    /// The grid name; duplicated names carry an index, `name[N]`, which
    /// [`read_grid`] accepts.
    pub name: String,
    /// Value type from the tree type string, e.g. `float`, `vec3s`, `int32`.
    pub value_type: String,
    pub grid_class: GridClass,
    pub stored_as_half: bool,
    /// True for float scalar grids with the standard tree layout.
    pub supported: bool,
}

/// An 8³ leaf node. `values` and `active` use OpenVDB's layout: voxel
/// `(x, y, z)` relative to `origin` sits at index `x * 64 + y * 8 + z`.
#[derive(Debug, Clone, PartialEq)]
pub struct VdbLeaf {
    pub origin: [i32; 3],
    pub values: Box<[f32; 512]>,
    pub active: [u64; 8],
}

/// A constant region: an internal-node or root tile. Inactive tiles are kept
/// only when their value differs from the background (level-set interiors).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VdbTile {
    pub origin: [i32; 3],
    /// Edge length in voxels: 8 (16³ node tile), 128 (32³ node tile) or 4096 (root tile).
    pub size: u32,
    pub value: f32,
    pub active: bool,
}

/// One float grid, flattened into leaves and tiles.
#[derive(Debug, Clone, PartialEq)]
pub struct VdbGrid {
    pub name: String,
    pub grid_class: GridClass,
    pub file_version: u32,
    pub stored_as_half: bool,
    /// `none`, or `zip`/`blosc`/`active-mask` joined with ` + `.
    pub compression: String,
    pub background: f32,
    /// Row-major affine map, world = M · (i, j, k, 1).
    pub index_to_world: [[f64; 4]; 4],
    pub leaves: Vec<VdbLeaf>,
    pub tiles: Vec<VdbTile>,
}

impl VdbGrid {
    /// Active voxels in leaves plus the volume of active tiles.
    pub fn active_voxel_count(&self) -> u64 {
        let leaves: u64 = self
            .leaves
            .iter()
            .map(|l| l.active.iter().map(|w| w.count_ones() as u64).sum::<u64>())
            .sum();
        let tiles: u64 = self
            .tiles
            .iter()
            .filter(|t| t.active)
            .map(|t| (t.size as u64).pow(3))
            .sum();
        leaves + tiles
    }

    /// Inclusive index-space box of the active voxels, as `vdb_print` shows it.
    pub fn active_bbox(&self) -> Option<([i32; 3], [i32; 3])> {
        let mut lo = [i32::MAX; 3];
        let mut hi = [i32::MIN; 3];
        let mut any = false;
        let mut grow = |a: [i32; 3], b: [i32; 3]| {
            any = true;
            for c in 0..3 {
                lo[c] = lo[c].min(a[c]);
                hi[c] = hi[c].max(b[c]);
            }
        };
        for leaf in &self.leaves {
            for_each_active(&leaf.active, |idx| {
                let p = leaf_coord(leaf.origin, idx);
                grow(p, p);
            });
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            let e = t.size as i32 - 1;
            let b = [0, 1, 2].map(|c| t.origin[c].saturating_add(e));
            grow(t.origin, b);
        }
        any.then_some((lo, hi))
    }

    /// Smallest and largest active value (leaf voxels and active tiles).
    pub fn active_value_range(&self) -> Option<(f32, f32)> {
        let mut range: Option<(f32, f32)> = None;
        let mut add = |v: f32| {
            range = Some(match range {
                None => (v, v),
                Some((a, b)) => (a.min(v), b.max(v)),
            })
        };
        for leaf in &self.leaves {
            for_each_active(&leaf.active, |idx| add(leaf.values[idx]));
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            add(t.value);
        }
        range
    }

    /// Sum of active values, each tile counted once per voxel it covers.
    pub fn active_value_sum(&self) -> f64 {
        let mut sum = 0.0f64;
        for leaf in &self.leaves {
            for_each_active(&leaf.active, |idx| sum += leaf.values[idx] as f64);
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            sum += t.value as f64 * (t.size as f64).powi(3);
        }
        sum
    }

    /// The value stored at `ijk`: the leaf voxel, else the innermost tile,
    /// else the background. A linear search, meant for tests and tools.
    pub fn value_at(&self, ijk: [i32; 3]) -> f32 {
        let leaf_origin = ijk.map(|v| v & !7);
        if let Some(leaf) = self.leaves.iter().find(|l| l.origin == leaf_origin) {
            let idx = (((ijk[0] & 7) << 6) | ((ijk[1] & 7) << 3) | (ijk[2] & 7)) as usize;
            return leaf.values[idx];
        }
        let inside = |t: &&VdbTile| {
            (0..3).all(|c| {
                let d = ijk[c] as i64 - t.origin[c] as i64;
                d >= 0 && d < t.size as i64
            })
        };
        match self.tiles.iter().filter(inside).min_by_key(|t| t.size) {
            Some(t) => t.value,
            None => self.background,
        }
    }
}

fn leaf_coord(origin: [i32; 3], idx: usize) -> [i32; 3] {
    let i = idx as i32;
    [
        origin[0].wrapping_add(i >> 6),
        origin[1].wrapping_add((i >> 3) & 7),
        origin[2].wrapping_add(i & 7),
    ]
}

fn for_each_active(mask: &[u64], mut f: impl FnMut(usize)) {
    for (w, &word) in mask.iter().enumerate() {
        let mut bits = word;
        while bits != 0 {
            let b = bits.trailing_zeros() as usize;
            f(w * 64 + b);
            bits &= bits - 1;
        }
    }
}

fn bit_on(mask: &[u64], idx: usize) -> bool {
    mask[idx / 64] >> (idx % 64) & 1 == 1
}

// ---------------------------------------------------------------------------
// Public entry points

/// Lists the grids of a file with their types, without reading any tree.
pub fn list_grids(path: &Path) -> Result<Vec<VdbGridDescriptor>> {
    list_grids_limit(path, WHOLE_FILE_LIMIT)
}

/// [`list_grids`] on bytes already in memory; `path` only names the source
/// in error messages.
pub fn list_grids_from_bytes(path: &Path, bytes: &[u8]) -> Result<Vec<VdbGridDescriptor>> {
    let file = parse_header(path, bytes)?;
    file.descs
        .iter()
        .map(|d| {
            let mut r = Reader::new(path, bytes, grid_context(&d.display_name));
            r.seek(d.grid_pos, "grid")?;
            describe(d, &mut r)
        })
        .collect()
}

/// Reads one float grid. `name = None` picks `density`, else the first float
/// scalar grid.
pub fn read_grid(path: &Path, name: Option<&str>) -> Result<VdbGrid> {
    read_grid_limit(path, name, WHOLE_FILE_LIMIT)
}

/// Same as [`read_grid`] from bytes already in memory (used by the fuzz
/// target). `path` is only used in messages.
pub fn parse_grid(path: &Path, bytes: &[u8], name: Option<&str>) -> Result<VdbGrid> {
    let file = parse_header(path, bytes)?;
    let desc = select_grid(path, &file, name)?;
    let mut r = Reader::new(path, bytes, grid_context(&desc.display_name));
    let (grid, _end) = read_float_grid(&mut r, &file, desc)?;
    Ok(grid)
}

fn describe(d: &GridDesc, r: &mut Reader) -> Result<VdbGridDescriptor> {
    let head = read_grid_head(r)?;
    Ok(VdbGridDescriptor {
        name: d.display_name.clone(),
        value_type: d.value_type.clone(),
        grid_class: head.class,
        stored_as_half: d.half,
        supported: d.supported,
    })
}

/// Files up to this size are read whole. Larger ones are read piecewise
/// (header, descriptors, then only the chosen grid's bytes), so picking one
/// grid out of a big multi-grid file costs that grid, not the file.
const WHOLE_FILE_LIMIT: u64 = 64 << 20;
/// Descriptors and grid metadata are read in windows of this size; a
/// larger one (absurdly long names or metadata) falls back to a whole read.
const WINDOW: usize = 1 << 20;

fn read_at(path: &Path, file: &mut std::fs::File, pos: usize, len: usize) -> Result<Vec<u8>> {
    use std::io::{Read, Seek, SeekFrom};
    file.seek(SeekFrom::Start(pos as u64))
        .map_err(|e| VolumeError::io(path, e))?;
    // `len` never exceeds what the file holds past `pos`.
    let mut buf = vec![0u8; len];
    file.read_exact(&mut buf)
        .map_err(|e| VolumeError::io(path, e))?;
    Ok(buf)
}

/// Opens `path`; returns the file and its header when the file is larger
/// than `limit` and has grid offsets, else the whole file's bytes.
enum Opened {
    Piecewise(std::fs::File, FileHeader),
    Whole(Vec<u8>),
}

fn open(path: &Path, limit: u64) -> Result<Opened> {
    let mut file = std::fs::File::open(path).map_err(|e| VolumeError::io(path, e))?;
    let len = file.metadata().map_err(|e| VolumeError::io(path, e))?.len();
    if len > limit {
        if let Ok(len) = usize::try_from(len) {
            if let Some(header) = header_from_file(path, &mut file, len)? {
                return Ok(Opened::Piecewise(file, header));
            }
        }
    }
    let bytes = std::fs::read(path).map_err(|e| VolumeError::io(path, e))?;
    Ok(Opened::Whole(bytes))
}

/// Parses header and descriptors from windows of the file; `None` when the
/// file has to be read whole (no grid offsets, or oversized header parts).
fn header_from_file(
    path: &Path,
    file: &mut std::fs::File,
    len: usize,
) -> Result<Option<FileHeader>> {
    let head = read_at(path, file, 0, len.min(WINDOW))?;
    let mut r = Reader::new(path, &head, "in file header".to_string());
    let pre = match parse_preamble(&mut r, len) {
        Ok(p) => p,
        Err(_) if head.len() < len => return Ok(None),
        Err(e) => return Err(e),
    };
    if !pre.has_offsets {
        return Ok(None);
    }
    let mut pos = pre.pos;
    let mut descs = Vec::new();
    for i in 0..pre.count {
        let win = read_at(path, file, pos, (len - pos).min(WINDOW))?;
        let mut r = Reader::window(path, &win, pos, String::new());
        let (desc, end) = match parse_descriptor(&mut r, i) {
            Ok(v) => v,
            Err(_) if win.len() < len - pos => return Ok(None),
            Err(e) => return Err(e),
        };
        check_offsets(&r, &desc, end, len)?;
        pos = desc.end_pos;
        descs.push(desc);
    }
    Ok(Some(FileHeader {
        version: pre.version,
        descs,
    }))
}

fn check_offsets(r: &Reader, desc: &GridDesc, end: i64, len: usize) -> Result<()> {
    if end < 0 || desc.end_pos > len {
        return Err(r.fail(format!(
            "invalid grid offsets (grid {}, end {end}; file has {len} bytes)",
            desc.grid_pos
        )));
    }
    Ok(())
}

fn list_grids_limit(path: &Path, limit: u64) -> Result<Vec<VdbGridDescriptor>> {
    let (mut file, header) = match open(path, limit)? {
        Opened::Whole(bytes) => return list_grids_from_bytes(path, &bytes),
        Opened::Piecewise(file, header) => (file, header),
    };
    let mut out = Vec::new();
    for d in &header.descs {
        let span = d.end_pos - d.grid_pos;
        let mut win = read_at(path, &mut file, d.grid_pos, span.min(WINDOW))?;
        let mut r = Reader::window(path, &win, d.grid_pos, grid_context(&d.display_name));
        let described = match describe(d, &mut r) {
            Err(_) if span > WINDOW => {
                win = read_at(path, &mut file, d.grid_pos, span)?;
                let mut r = Reader::window(path, &win, d.grid_pos, grid_context(&d.display_name));
                describe(d, &mut r)?
            }
            other => other?,
        };
        out.push(described);
    }
    Ok(out)
}

fn read_grid_limit(path: &Path, name: Option<&str>, limit: u64) -> Result<VdbGrid> {
    let (mut file, header) = match open(path, limit)? {
        Opened::Whole(bytes) => return parse_grid(path, &bytes, name),
        Opened::Piecewise(file, header) => (file, header),
    };
    let desc = select_grid(path, &header, name)?;
    if !desc.instance_parent.is_empty() {
        // The tree lives with the parent grid, elsewhere in the file.
        let bytes = std::fs::read(path).map_err(|e| VolumeError::io(path, e))?;
        return parse_grid(path, &bytes, name);
    }
    let bytes = read_at(path, &mut file, desc.grid_pos, desc.end_pos - desc.grid_pos)?;
    let mut r = Reader::window(
        path,
        &bytes,
        desc.grid_pos,
        grid_context(&desc.display_name),
    );
    Ok(read_float_grid(&mut r, &header, desc)?.0)
}

fn select_grid<'f>(path: &Path, file: &'f FileHeader, name: Option<&str>) -> Result<&'f GridDesc> {
    let Some(name) = name else {
        let pick = file
            .descs
            .iter()
            .find(|d| d.supported && d.name == "density")
            .or_else(|| file.descs.iter().find(|d| d.supported));
        return pick.ok_or_else(|| {
            let listed: Vec<String> = file
                .descs
                .iter()
                .map(|d| format!("`{}` ({})", d.display_name, d.value_type))
                .collect();
            VolumeError::format(
                path,
                format!(
                    "no float grid to read (grids in file: {})",
                    if listed.is_empty() {
                        "none".to_string()
                    } else {
                        listed.join(", ")
                    }
                ),
            )
        });
    };
    let unique = match (name.find('['), name.strip_suffix(']')) {
        (Some(open), Some(body)) => format!("{}{}{}", &body[..open], NAME_SEP, &body[open + 1..]),
        _ => name.to_string(),
    };
    let found = file
        .descs
        .iter()
        .find(|d| d.unique_name == name || d.unique_name == unique)
        .or_else(|| file.descs.iter().find(|d| d.name == name));
    match found {
        Some(d) if d.supported => Ok(d),
        Some(d) => Err(VolumeError::format(
            path,
            format!(
                "grid `{}` has value type `{}` ({}); only float grids ({}) can be read",
                d.display_name, d.value_type, d.type_name, FLOAT_TREE
            ),
        )),
        None => Err(VolumeError::GridNotFound {
            path: path.to_path_buf(),
            grid: name.to_string(),
            available: file.descs.iter().map(|d| d.display_name.clone()).collect(),
        }),
    }
}

// ---------------------------------------------------------------------------
// Byte reader

/// A bounds-checked little-endian cursor whose errors carry file, context
/// (which grid or header part) and offset.
struct Reader<'a> {
    path: &'a Path,
    /// The file, or a window of it starting at file offset `base`.
    data: &'a [u8],
    base: usize,
    pos: usize,
    context: String,
}

fn grid_context(name: &str) -> String {
    format!("in grid `{name}`")
}

impl<'a> Reader<'a> {
    fn new(path: &'a Path, data: &'a [u8], context: String) -> Self {
        Reader {
            path,
            data,
            base: 0,
            pos: 0,
            context,
        }
    }

    fn window(path: &'a Path, data: &'a [u8], base: usize, context: String) -> Self {
        Reader {
            path,
            data,
            base,
            pos: 0,
            context,
        }
    }

    /// Position in the file, for messages and seeks.
    fn offset(&self) -> usize {
        self.base + self.pos
    }

    fn fail_at(&self, pos: usize, msg: impl std::fmt::Display) -> VolumeError {
        VolumeError::format(self.path, format!("{msg} {} at offset {pos}", self.context))
    }

    fn fail(&self, msg: impl std::fmt::Display) -> VolumeError {
        self.fail_at(self.offset(), msg)
    }

    fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        if n > self.remaining() {
            return Err(self.fail(format!(
                "truncated {what} (needs {n} bytes, {} left)",
                self.remaining()
            )));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let s = self.take(N, what)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }

    fn u8(&mut self, what: &str) -> Result<u8> {
        Ok(self.array::<1>(what)?[0])
    }
    fn u32(&mut self, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }
    fn i32(&mut self, what: &str) -> Result<i32> {
        Ok(i32::from_le_bytes(self.array(what)?))
    }
    fn i64(&mut self, what: &str) -> Result<i64> {
        Ok(i64::from_le_bytes(self.array(what)?))
    }
    fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.array(what)?))
    }
    fn f64(&mut self, what: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }
    fn vec3d(&mut self, what: &str) -> Result<[f64; 3]> {
        Ok([self.f64(what)?, self.f64(what)?, self.f64(what)?])
    }
    fn coord(&mut self, what: &str) -> Result<[i32; 3]> {
        Ok([self.i32(what)?, self.i32(what)?, self.i32(what)?])
    }

    /// A `u32`-length-prefixed string. Names are ASCII in practice; anything
    /// else is kept lossily so that it can still be shown in messages.
    fn string(&mut self, what: &str) -> Result<String> {
        let start = self.offset();
        let len = self.u32(what)? as usize;
        if len > self.remaining() {
            return Err(self.fail_at(
                start,
                format!(
                    "{what} claims {len} bytes but only {} remain",
                    self.remaining()
                ),
            ));
        }
        let s = self.take(len, what)?;
        Ok(String::from_utf8_lossy(s).into_owned())
    }

    fn mask(&mut self, words: usize, what: &str) -> Result<Vec<u64>> {
        let s = self.take(words * 8, what)?;
        Ok(s.chunks_exact(8)
            .map(|c| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect())
    }

    fn seek(&mut self, pos: usize, what: &str) -> Result<()> {
        match pos.checked_sub(self.base) {
            Some(rel) if rel <= self.data.len() => {
                self.pos = rel;
                Ok(())
            }
            _ => Err(self.fail(format!(
                "{what} offset {pos} lies outside the bytes read ({}..{})",
                self.base,
                self.base + self.data.len()
            ))),
        }
    }
}

// ---------------------------------------------------------------------------
// File header and grid descriptors

struct FileHeader {
    version: u32,
    descs: Vec<GridDesc>,
}

struct GridDesc {
    /// As stored, possibly with a `\x1e N` suffix.
    unique_name: String,
    /// Without the suffix.
    name: String,
    /// `name[N]` when there was a suffix; what users see and may pass back.
    display_name: String,
    /// Tree type without the `_HalfFloat` suffix, e.g. `Tree_float_5_4_3`.
    type_name: String,
    value_type: String,
    half: bool,
    supported: bool,
    instance_parent: String,
    grid_pos: usize,
    end_pos: usize,
}

/// What precedes the grid descriptors.
struct Preamble {
    version: u32,
    has_offsets: bool,
    count: usize,
    /// Offset of the first descriptor.
    pos: usize,
}

/// Parses magic, version, flags, UUID, file metadata and the grid count.
/// `file_len` bounds the grid count when `r` holds only a window of the file.
fn parse_preamble(r: &mut Reader, file_len: usize) -> Result<Preamble> {
    let path = r.path;
    let magic = r.array::<8>("magic number").map_err(|_| {
        VolumeError::format(path, "not an OpenVDB file (shorter than its magic number)")
    })?;
    if magic != MAGIC {
        return Err(VolumeError::format(
            path,
            "not an OpenVDB file (bad magic number)",
        ));
    }
    let version = r.u32("file format version")?;
    if version < MIN_FILE_VERSION {
        return Err(r.fail(format!(
            "file format version {version} is older than the oldest supported ({MIN_FILE_VERSION})"
        )));
    }
    if version > MAX_FILE_VERSION {
        return Err(r.fail(format!(
            "file format version {version} is newer than this reader supports ({MIN_FILE_VERSION}–{MAX_FILE_VERSION})"
        )));
    }
    let _lib_major = r.u32("library version")?;
    let _lib_minor = r.u32("library version")?;
    let has_offsets = r.u8("grid offsets flag")? != 0;
    r.take(36, "file UUID")?;
    r.context = "in file metadata".to_string();
    read_metamap(r)?;
    r.context = "in grid table".to_string();
    let count = r.i32("grid count")?;
    // A descriptor holds three strings and three offsets: at least 36 bytes.
    let left = file_len.saturating_sub(r.offset());
    if count < 0 || count as usize > left / 36 {
        return Err(r.fail(format!("implausible grid count {count} for the file size")));
    }
    Ok(Preamble {
        version,
        has_offsets,
        count: count as usize,
        pos: r.offset(),
    })
}

/// Parses descriptor `i` at the reader's position; returns it with the
/// stored end-of-grid offset (meaningful only in files with grid offsets).
fn parse_descriptor(r: &mut Reader, i: usize) -> Result<(GridDesc, i64)> {
    r.context = format!("in descriptor of grid #{i}");
    let unique_name = r.string("grid name")?;
    let raw_type = r.string("grid type")?;
    let instance_parent = r.string("instance parent name")?;
    let grid_pos = r.i64("grid offset")?;
    // Not needed (buffers follow the topology) and left 0 for instances.
    let _block_pos = r.i64("grid block offset")?;
    let end_pos = r.i64("grid end offset")?;
    let (type_name, half) = match raw_type.strip_suffix(HALF_SUFFIX) {
        Some(t) => (t.to_string(), true),
        None => (raw_type.clone(), false),
    };
    let (name, display_name) = match unique_name.find(NAME_SEP) {
        Some(p) => (
            unique_name[..p].to_string(),
            format!("{}[{}]", &unique_name[..p], &unique_name[p + 1..]),
        ),
        None => (unique_name.clone(), unique_name.clone()),
    };
    let value_type = value_type_of(&type_name);
    let supported = type_name == FLOAT_TREE;
    r.context = grid_context(&display_name);
    let desc = GridDesc {
        unique_name,
        name,
        display_name,
        type_name,
        value_type,
        half,
        supported,
        instance_parent,
        grid_pos: 0,
        end_pos: 0,
    };
    let here = r.offset() as i64;
    if grid_pos < here || end_pos < grid_pos {
        // Streams store zeros here; the caller decides whether that matters.
        return Ok((
            GridDesc {
                grid_pos: r.offset(),
                ..desc
            },
            -1,
        ));
    }
    Ok((
        GridDesc {
            grid_pos: grid_pos as usize,
            end_pos: end_pos as usize,
            ..desc
        },
        end_pos,
    ))
}

fn parse_header(path: &Path, data: &[u8]) -> Result<FileHeader> {
    let mut r = Reader::new(path, data, "in file header".to_string());
    let pre = parse_preamble(&mut r, data.len())?;
    let mut descs: Vec<GridDesc> = Vec::new();
    for i in 0..pre.count {
        let (mut desc, end) = parse_descriptor(&mut r, i)?;
        if pre.has_offsets {
            check_offsets(&r, &desc, end, data.len())?;
            r.seek(desc.end_pos, "grid end")?;
        } else {
            // Without offsets the only way past a grid is to parse it.
            desc.grid_pos = r.offset();
            let file = FileHeader {
                version: pre.version,
                descs: Vec::new(),
            };
            let end = if !desc.instance_parent.is_empty() {
                read_grid_head(&mut r)?;
                read_transform(&mut r)?;
                r.offset()
            } else if desc.supported {
                read_float_grid(&mut r, &file, &desc)?.1
            } else {
                return Err(r.fail(format!(
                    "file has no grid offsets, so grid of type `{}` cannot be skipped",
                    desc.type_name
                )));
            };
            r.seek(end, "grid end")?;
            desc.end_pos = end;
        }
        descs.push(desc);
    }
    Ok(FileHeader {
        version: pre.version,
        descs,
    })
}

/// `Tree_float_5_4_3` → `float`, `Tree_vec3s_5_4_3` → `vec3s`.
fn value_type_of(type_name: &str) -> String {
    let body = type_name.strip_prefix("Tree_").unwrap_or(type_name);
    let mut parts: Vec<&str> = body.split('_').collect();
    while parts.len() > 1
        && parts
            .last()
            .is_some_and(|p| p.chars().all(|c| c.is_ascii_digit()))
    {
        parts.pop();
    }
    parts.join("_")
}

/// Reads a metadata map and returns `(name, type, raw value)` entries.
fn read_metamap<'a>(r: &mut Reader<'a>) -> Result<Vec<(String, String, &'a [u8])>> {
    let count = r.u32("metadata count")? as usize;
    // Each entry has two length-prefixed strings and a size: 12 bytes at least.
    if count > r.remaining() / 12 {
        return Err(r.fail(format!("implausible metadata count {count}")));
    }
    let mut out = Vec::new();
    for _ in 0..count {
        let name = r.string("metadata name")?;
        let ty = r.string("metadata type")?;
        let size = r.u32("metadata size")? as usize;
        let value = r.take(size, "metadata value")?;
        out.push((name, ty, value));
    }
    Ok(out)
}

// ---------------------------------------------------------------------------
// Grid header: compression, metadata, transform

struct GridHead {
    compression: u32,
    class: GridClass,
}

fn read_grid_head(r: &mut Reader) -> Result<GridHead> {
    let compression = r.u32("compression flags")?;
    if compression & !(COMPRESS_ZIP | COMPRESS_ACTIVE_MASK | COMPRESS_BLOSC) != 0 {
        return Err(r.fail(format!("unknown compression flags {compression:#x}")));
    }
    let meta = read_metamap(r)?;
    let class = meta
        .iter()
        .find(|(n, t, _)| n == "class" && t == "string")
        .map(|(_, _, v)| GridClass::from_meta(&String::from_utf8_lossy(v)))
        .unwrap_or(GridClass::Unknown);
    Ok(GridHead { compression, class })
}

fn compression_name(c: u32) -> String {
    let mut parts = Vec::new();
    if c & COMPRESS_ZIP != 0 {
        parts.push("zip");
    }
    if c & COMPRESS_BLOSC != 0 {
        parts.push("blosc");
    }
    if c & COMPRESS_ACTIVE_MASK != 0 {
        parts.push("active-mask");
    }
    if parts.is_empty() {
        "none".to_string()
    } else {
        parts.join(" + ")
    }
}

/// Reads a map and returns it as a row-major matrix for column vectors.
/// OpenVDB multiplies row vectors (`p' = p · M`), hence the transposes.
fn read_transform(r: &mut Reader) -> Result<[[f64; 4]; 4]> {
    let at = r.offset();
    let ty = r.string("transform map type")?;
    let mut m = [[0.0f64; 4]; 4];
    m[3][3] = 1.0;
    let diag = |m: &mut [[f64; 4]; 4], s: [f64; 3]| {
        for c in 0..3 {
            m[c][c] = s[c];
        }
    };
    match ty.as_str() {
        "UniformScaleMap" | "ScaleMap" => {
            let scale = r.vec3d("scale map")?;
            // voxel size, inverse scale, inverse squared scale, inverse twice scale
            r.take(4 * 24, "scale map")?;
            diag(&mut m, scale);
        }
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let t = r.vec3d("scale-translate map")?;
            let scale = r.vec3d("scale-translate map")?;
            r.take(4 * 24, "scale-translate map")?;
            diag(&mut m, scale);
            for c in 0..3 {
                m[c][3] = t[c];
            }
        }
        "TranslationMap" => {
            let t = r.vec3d("translation map")?;
            diag(&mut m, [1.0; 3]);
            for c in 0..3 {
                m[c][3] = t[c];
            }
        }
        "AffineMap" | "UnitaryMap" => {
            let mut a = [[0.0f64; 4]; 4];
            for row in a.iter_mut() {
                for v in row.iter_mut() {
                    *v = r.f64("affine map matrix")?;
                }
            }
            if a[0][3] != 0.0 || a[1][3] != 0.0 || a[2][3] != 0.0 || a[3][3] != 1.0 {
                return Err(r.fail_at(at, "affine map matrix is projective, not affine"));
            }
            for row in 0..3 {
                for col in 0..4 {
                    m[row][col] = a[col][row];
                }
            }
        }
        other => {
            return Err(r.fail_at(
                at,
                format!("unsupported transform map type `{other}` (only linear maps can be read)"),
            ))
        }
    }
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Err(r.fail_at(at, format!("{ty} has non-finite entries")));
    }
    Ok(m)
}

// ---------------------------------------------------------------------------
// Tree

/// What node buffers need to know to decode: the stream settings OpenVDB
/// keeps on its `istream`.
struct Codec {
    compression: u32,
    half: bool,
    background: f32,
}

struct LeafTopo {
    origin: [i32; 3],
    mask: [u64; 8],
}

struct Tree {
    background: f32,
    leaves: Vec<VdbLeaf>,
    tiles: Vec<VdbTile>,
}

/// Reads the grid at `desc.grid_pos`; returns it and the offset just past it.
fn read_float_grid(r: &mut Reader, file: &FileHeader, desc: &GridDesc) -> Result<(VdbGrid, usize)> {
    r.seek(desc.grid_pos, "grid")?;
    let head = read_grid_head(r)?;
    let index_to_world = read_transform(r)?;
    let end;
    let tree = if desc.instance_parent.is_empty() {
        let t = read_tree(r, head.compression, desc.half)?;
        end = r.offset();
        t
    } else {
        end = r.offset();
        let parent = file
            .descs
            .iter()
            .find(|d| d.unique_name == desc.instance_parent && d.instance_parent.is_empty())
            .ok_or_else(|| {
                r.fail(format!(
                    "instance parent `{}` not found",
                    desc.instance_parent
                ))
            })?;
        if !parent.supported || parent.half != desc.half {
            return Err(r.fail(format!(
                "instance parent `{}` is not a matching float grid",
                parent.display_name
            )));
        }
        let mut pr = Reader::window(r.path, r.data, r.base, grid_context(&parent.display_name));
        pr.seek(parent.grid_pos, "grid")?;
        let phead = read_grid_head(&mut pr)?;
        read_transform(&mut pr)?;
        read_tree(&mut pr, phead.compression, parent.half)?
    };
    let grid = VdbGrid {
        name: desc.name.clone(),
        grid_class: head.class,
        file_version: file.version,
        stored_as_half: desc.half,
        compression: compression_name(head.compression),
        background: tree.background,
        index_to_world,
        leaves: tree.leaves,
        tiles: tree.tiles,
    };
    Ok((grid, end))
}

fn read_tree(r: &mut Reader, compression: u32, half: bool) -> Result<Tree> {
    // Trees once held several buffers; OpenVDB only warns when this is not 1.
    let _buffer_count = r.i32("tree buffer count")?;
    let background = r.f32("background value")?;
    let num_tiles = r.u32("root tile count")? as usize;
    let num_children = r.u32("root child count")? as usize;
    const TILE_BYTES: usize = 12 + 4 + 1;
    // origin + two 32³ masks + at least the per-node metadata byte
    const CHILD_MIN_BYTES: usize = 12 + 2 * 4096 + 1;
    if num_tiles > r.remaining() / TILE_BYTES {
        return Err(r.fail(format!("implausible root tile count {num_tiles}")));
    }
    let tile_bytes = num_tiles * TILE_BYTES;
    if num_children > (r.remaining() - tile_bytes) / CHILD_MIN_BYTES {
        return Err(r.fail(format!("implausible root child count {num_children}")));
    }
    let codec = Codec {
        compression,
        half,
        background,
    };
    let mut tiles = Vec::new();
    for _ in 0..num_tiles {
        let origin = r.coord("root tile")?.map(|v| v & !4095);
        let value = r.f32("root tile value")?;
        let active = r.u8("root tile state")? != 0;
        if active || value != background {
            tiles.push(VdbTile {
                origin,
                size: 4096,
                value,
                active,
            });
        }
    }
    let mut leaf_topos = Vec::new();
    let mut origins = std::collections::HashSet::new();
    for _ in 0..num_children {
        let at = r.offset();
        let origin = r.coord("root child origin")?.map(|v| v & !4095);
        if !origins.insert(origin) {
            return Err(r.fail_at(at, format!("duplicate root child at {origin:?}")));
        }
        read_internal(r, &codec, origin, 5, &mut tiles, &mut leaf_topos)?;
    }
    // Buffers follow in the same depth-first order as the topology.
    let mut leaves = Vec::new();
    for topo in leaf_topos {
        // OpenVDB seeks over this copy of the mask and keeps the topology's.
        r.take(64, "leaf value mask")?;
        let mut values = Box::new([0.0f32; 512]);
        let what = format!("leaf buffer at {:?}", topo.origin);
        read_compressed_values(r, &codec, &mut values[..], &topo.mask, &what)?;
        leaves.push(VdbLeaf {
            origin: topo.origin,
            values,
            active: topo.mask,
        });
    }
    Ok(Tree {
        background,
        leaves,
        tiles,
    })
}

/// Reads the topology of a 32³ (`level` 5) or 16³ (`level` 4) internal node:
/// child mask, value mask, the tile values, then each child in index order.
fn read_internal(
    r: &mut Reader,
    codec: &Codec,
    origin: [i32; 3],
    level: u32,
    tiles: &mut Vec<VdbTile>,
    leaves: &mut Vec<LeafTopo>,
) -> Result<()> {
    let log2 = level;
    let child_log2 = if level == 5 { 7 } else { 3 };
    let n = 1usize << (3 * log2);
    let child_mask = r.mask(n / 64, "internal node child mask")?;
    let value_mask = r.mask(n / 64, "internal node value mask")?;
    let mut values = vec![0.0f32; n];
    let what = format!("tile values of internal node at {origin:?}");
    read_compressed_values(r, codec, &mut values, &value_mask, &what)?;
    let dim_mask = (1usize << log2) - 1;
    let child_origin = |idx: usize| {
        let x = (idx >> (2 * log2)) as i32;
        let y = ((idx >> log2) & dim_mask) as i32;
        let z = (idx & dim_mask) as i32;
        [
            origin[0].wrapping_add(x << child_log2),
            origin[1].wrapping_add(y << child_log2),
            origin[2].wrapping_add(z << child_log2),
        ]
    };
    for (idx, &value) in values.iter().enumerate() {
        if bit_on(&child_mask, idx) {
            continue;
        }
        let active = bit_on(&value_mask, idx);
        if active || value != codec.background {
            tiles.push(VdbTile {
                origin: child_origin(idx),
                size: 1 << child_log2,
                value,
                active,
            });
        }
    }
    let mut result = Ok(());
    for_each_active(&child_mask, |idx| {
        if result.is_err() {
            return;
        }
        let o = child_origin(idx);
        result = if level == 5 {
            read_internal(r, codec, o, 4, tiles, leaves)
        } else {
            r.mask(8, "leaf value mask").map(|m| {
                let mut mask = [0u64; 8];
                mask.copy_from_slice(&m);
                leaves.push(LeafTopo { origin: o, mask });
            })
        };
    });
    result
}

/// Per-node indicator of how inactive values were stored (OpenVDB's
/// `io::Compression.h` enum, in file order).
const NO_MASK_OR_INACTIVE_VALS: u8 = 0;
const NO_MASK_AND_MINUS_BG: u8 = 1;
const NO_MASK_AND_ONE_INACTIVE_VAL: u8 = 2;
const MASK_AND_NO_INACTIVE_VALS: u8 = 3;
const MASK_AND_ONE_INACTIVE_VAL: u8 = 4;
const MASK_AND_TWO_INACTIVE_VALS: u8 = 5;
const NO_MASK_AND_ALL_VALS: u8 = 6;

/// Fills `out` (one value per bit of `value_mask`) from a node buffer that
/// may hold only the active values, in half or full precision, raw, Zip or
/// Blosc compressed. Inactive values are rebuilt from the background, the
/// stored inactive values and the selection mask.
fn read_compressed_values(
    r: &mut Reader,
    codec: &Codec,
    out: &mut [f32],
    value_mask: &[u64],
    what: &str,
) -> Result<()> {
    let n = out.len();
    let at = r.offset();
    let meta = r.u8("node compression metadata")?;
    if meta > NO_MASK_AND_ALL_VALS {
        return Err(r.fail_at(
            at,
            format!("invalid compression metadata byte {meta} for {what}"),
        ));
    }
    let bg = codec.background;
    let mut inactive0 = match meta {
        NO_MASK_OR_INACTIVE_VALS => bg,
        NO_MASK_AND_MINUS_BG | MASK_AND_NO_INACTIVE_VALS => -bg,
        // Replaced below by the stored value; OpenVDB starts from -background too.
        _ => -bg,
    };
    let mut inactive1 = bg;
    if matches!(
        meta,
        NO_MASK_AND_ONE_INACTIVE_VAL | MASK_AND_ONE_INACTIVE_VAL | MASK_AND_TWO_INACTIVE_VALS
    ) {
        // Always full precision, even in half-float grids.
        inactive0 = r.f32("inactive value")?;
        if meta == MASK_AND_TWO_INACTIVE_VALS {
            inactive1 = r.f32("inactive value")?;
        }
    }
    let selection = if matches!(
        meta,
        MASK_AND_NO_INACTIVE_VALS | MASK_AND_ONE_INACTIVE_VAL | MASK_AND_TWO_INACTIVE_VALS
    ) {
        Some(r.mask(n / 64, "inactive value selection mask")?)
    } else {
        None
    };
    let mask_compressed = codec.compression & COMPRESS_ACTIVE_MASK != 0;
    let count = if mask_compressed && meta != NO_MASK_AND_ALL_VALS {
        value_mask.iter().map(|w| w.count_ones() as usize).sum()
    } else {
        n
    };
    let values = read_values(r, codec, count, what)?;
    if count == n {
        out.copy_from_slice(&values);
    } else {
        let mut next = values.iter();
        for (idx, slot) in out.iter_mut().enumerate() {
            *slot = if bit_on(value_mask, idx) {
                // `count` equals the number of set bits, so this never runs dry.
                next.next().copied().unwrap_or(bg)
            } else if selection.as_ref().is_some_and(|s| bit_on(s, idx)) {
                inactive1
            } else {
                inactive0
            };
        }
    }
    Ok(())
}

/// Reads `count` values, as half or full floats, through the grid's codec.
fn read_values(r: &mut Reader, codec: &Codec, count: usize, what: &str) -> Result<Vec<f32>> {
    if codec.half {
        // OpenVDB writes nothing at all, not even a size, for empty half buffers.
        if count == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_chunk(r, codec, count * 2, what)?;
        Ok(bytes
            .chunks_exact(2)
            .map(|c| half::f16::from_bits(u16::from_le_bytes([c[0], c[1]])).to_f32())
            .collect())
    } else {
        let bytes = read_chunk(r, codec, count * 4, what)?;
        Ok(bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect())
    }
}

/// Reads `nbytes` of payload. Zip and Blosc chunks carry an `i64` size:
/// positive for compressed data, negative when the writer stored the bytes
/// as they are because compression did not pay off.
fn read_chunk<'a>(
    r: &mut Reader<'a>,
    codec: &Codec,
    nbytes: usize,
    what: &str,
) -> Result<std::borrow::Cow<'a, [u8]>> {
    use std::borrow::Cow;
    let blosc = codec.compression & COMPRESS_BLOSC != 0;
    let zip = codec.compression & COMPRESS_ZIP != 0;
    if !blosc && !zip {
        return Ok(Cow::Borrowed(r.take(nbytes, what)?));
    }
    let at = r.offset();
    let size = r.i64("compressed chunk size")?;
    if size <= 0 {
        if size.unsigned_abs() != nbytes as u64 {
            return Err(r.fail_at(
                at,
                format!(
                    "{what}: stored chunk of {} bytes, expected {nbytes}",
                    size.unsigned_abs()
                ),
            ));
        }
        return Ok(Cow::Borrowed(r.take(nbytes, what)?));
    }
    if size as u64 > r.remaining() as u64 {
        return Err(r.fail_at(
            at,
            format!(
                "truncated {what} (compressed chunk of {size} bytes, {} left)",
                r.remaining()
            ),
        ));
    }
    let src = r.take(size as usize, what)?;
    let out = if blosc {
        blosc::decompress(src, nbytes).map_err(|e| r.fail_at(at, format!("{what}: {e}")))?
    } else {
        let mut out = vec![0u8; nbytes];
        let mut z = flate2::Decompress::new(true);
        let produced = match z.decompress(src, &mut out, flate2::FlushDecompress::Finish) {
            Ok(_) => z.total_out() as usize,
            Err(e) => return Err(r.fail_at(at, format!("{what}: corrupt zlib data ({e})"))),
        };
        if produced != nbytes {
            return Err(r.fail_at(
                at,
                format!("{what}: zlib data decompressed to {produced} bytes, expected {nbytes}"),
            ));
        }
        out
    };
    Ok(Cow::Owned(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_type_from_tree_type() {
        assert_eq!(value_type_of("Tree_float_5_4_3"), "float");
        assert_eq!(value_type_of("Tree_vec3s_5_4_3"), "vec3s");
        assert_eq!(value_type_of("Tree_ptdataidx32_5_4_3"), "ptdataidx32");
        assert_eq!(value_type_of("weird"), "weird");
    }

    #[test]
    fn piecewise_reading_matches_whole_file() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/vdb");
        for file in [
            "multi.vdb",
            "tiles_f32_zip.vdb",
            "stream_tiles.vdb",
            "fog_half_blosc.vdb",
        ] {
            let path = dir.join(file);
            let bytes = std::fs::read(&path).unwrap();
            assert_eq!(
                list_grids_limit(&path, 0).unwrap(),
                list_grids_from_bytes(&path, &bytes).unwrap()
            );
            for d in list_grids_from_bytes(&path, &bytes)
                .unwrap()
                .iter()
                .filter(|d| d.supported)
            {
                let whole = parse_grid(&path, &bytes, Some(&d.name)).unwrap();
                let piecewise = read_grid_limit(&path, Some(&d.name), 0).unwrap();
                assert_eq!(whole, piecewise, "{file} / {}", d.name);
            }
            assert!(
                matches!(open(&path, 0).unwrap(), Opened::Piecewise(..))
                    != file.starts_with("stream")
            );
        }
    }

    #[test]
    fn compression_names() {
        assert_eq!(compression_name(0), "none");
        assert_eq!(compression_name(6), "blosc + active-mask");
        assert_eq!(compression_name(3), "zip + active-mask");
    }
}

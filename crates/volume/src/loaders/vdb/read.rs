//! Public entry points, and reading large files piecewise (header,
//! descriptors, then only the chosen grid's bytes).

use std::path::Path;

use super::format::{FLOAT_TREE, NAME_SEP, VEC3S_TREE};
use super::grid::{FileHeader, GridDesc, VdbGrid, VdbGridDescriptor};
use super::header::{check_offsets, parse_descriptor, parse_header, parse_preamble};
use super::metadata::read_grid_head;
use super::reader::{grid_context, Reader};
use super::tree::read_grid_at;
use crate::error::{Result, VolumeError};
use crate::loaders::grid_choice::{pick_default, ListedGrid};

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
    let [grid] = read_grid_limit::<1>(path, name, WHOLE_FILE_LIMIT)?;
    Ok(grid)
}

/// Same as [`read_grid`] from bytes already in memory (used by the fuzz
/// target). `path` is only used in messages.
pub fn parse_grid(path: &Path, bytes: &[u8], name: Option<&str>) -> Result<VdbGrid> {
    let [grid] = parse_grid_k::<1>(path, bytes, name)?;
    Ok(grid)
}

/// Reads one `vec3s` grid (velocity; stored in full or half precision) as
/// its x, y and z components: three float grids named `name.x`, `name.y`,
/// `name.z` with the same topology, transform and class. `name = None`
/// picks a `vec3s` grid named `vel`, `v` or `velocity` (in that order of
/// preference), else the first `vec3s` grid.
pub fn read_vec3_grid(path: &Path, name: Option<&str>) -> Result<[VdbGrid; 3]> {
    read_grid_limit::<3>(path, name, WHOLE_FILE_LIMIT)
}

/// Same as [`read_vec3_grid`] from bytes already in memory (used by the
/// fuzz target). `path` is only used in messages.
pub fn parse_vec3_grid(path: &Path, bytes: &[u8], name: Option<&str>) -> Result<[VdbGrid; 3]> {
    parse_grid_k::<3>(path, bytes, name)
}

/// A grid with `K` floats per value (1: `float`, 3: `vec3s`) from bytes.
fn parse_grid_k<const K: usize>(
    path: &Path,
    bytes: &[u8],
    name: Option<&str>,
) -> Result<[VdbGrid; K]> {
    let file = parse_header(path, bytes)?;
    let desc = select_grid(path, &file, name, K)?;
    let mut r = Reader::new(path, bytes, grid_context(&desc.display_name));
    Ok(read_grid_at::<K>(&mut r, &file, desc)?.0)
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

fn read_grid_limit<const K: usize>(
    path: &Path,
    name: Option<&str>,
    limit: u64,
) -> Result<[VdbGrid; K]> {
    let (mut file, header) = match open(path, limit)? {
        Opened::Whole(bytes) => return parse_grid_k::<K>(path, &bytes, name),
        Opened::Piecewise(file, header) => (file, header),
    };
    let desc = select_grid(path, &header, name, K)?;
    if !desc.instance_parent.is_empty() {
        // The tree lives with the parent grid, elsewhere in the file.
        let bytes = std::fs::read(path).map_err(|e| VolumeError::io(path, e))?;
        return parse_grid_k::<K>(path, &bytes, name);
    }
    let bytes = read_at(path, &mut file, desc.grid_pos, desc.end_pos - desc.grid_pos)?;
    let mut r = Reader::window(
        path,
        &bytes,
        desc.grid_pos,
        grid_context(&desc.display_name),
    );
    Ok(read_grid_at::<K>(&mut r, &header, desc)?.0)
}

impl ListedGrid for GridDesc {
    fn grid_name(&self) -> &str {
        &self.name
    }

    fn describe(&self) -> String {
        let half = if self.half { ", half" } else { "" };
        format!("`{}` ({}{half})", self.display_name, self.value_type)
    }
}

/// Picks the grid to read: by name (`name`, or `name[N]` for duplicated
/// names; a plain name picks the first), else by the default names, else
/// the first grid of the wanted type. A named grid of another type is an
/// error that names its type.
fn select_grid<'f>(
    path: &Path,
    file: &'f FileHeader,
    name: Option<&str>,
    k: usize,
) -> Result<&'f GridDesc> {
    let wanted = if k == 3 { "vec3s (velocity)" } else { "float" };
    let fits = |d: &GridDesc| d.components() == Some(k);
    let Some(name) = name else {
        return pick_default(path, &file.descs, k, fits, wanted);
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
    let Some(d) = found else {
        return Err(VolumeError::GridNotFound {
            path: path.to_path_buf(),
            grid: name.to_string(),
            available: file.descs.iter().map(|d| d.display_name.clone()).collect(),
        });
    };
    if fits(d) {
        return Ok(d);
    }
    let precision = if d.half { ", stored as half" } else { "" };
    let message = if k == 3 {
        format!(
            "grid `{}` has value type `{}` ({}{precision}); a velocity grid must be \
             vec3s ({VEC3S_TREE}, float or half precision)",
            d.display_name, d.value_type, d.type_name
        )
    } else {
        let hint = if d.type_name == VEC3S_TREE {
            "; vec3s grids are read as three components by read_vec3_grid"
        } else {
            ""
        };
        format!(
            "grid `{}` has value type `{}` ({}{precision}); only float grids ({}) can be read{hint}",
            d.display_name, d.value_type, d.type_name, FLOAT_TREE
        )
    };
    Err(VolumeError::format(path, message))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_reading_matches_whole_file() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/vdb");
        for file in [
            "multi.vdb",
            "tiles_f32_zip.vdb",
            "stream_tiles.vdb",
            "fog_half_blosc.vdb",
            "density_vel.vdb",
            "vec3_instance.vdb",
            "vec3_stream.vdb",
            "vec3_half_zip.vdb",
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
                let [piecewise] = read_grid_limit::<1>(&path, Some(&d.name), 0).unwrap();
                assert_eq!(whole, piecewise, "{file} / {}", d.name);
            }
            for d in list_grids_from_bytes(&path, &bytes)
                .unwrap()
                .iter()
                .filter(|d| d.value_type == "vec3s")
            {
                let whole = parse_vec3_grid(&path, &bytes, Some(&d.name)).unwrap();
                let piecewise = read_grid_limit::<3>(&path, Some(&d.name), 0).unwrap();
                assert_eq!(whole, piecewise, "{file} / {}", d.name);
            }
            assert!(
                matches!(open(&path, 0).unwrap(), Opened::Piecewise(..)) != file.contains("stream")
            );
        }
    }
}

//! File header (magic, version, file metadata) and the grid descriptors
//! that follow it.

use std::path::Path;

use super::format::{FLOAT_TREE, HALF_SUFFIX, MAGIC, NAME_SEP};
use super::grid::{FileHeader, GridDesc};
use super::metadata::{read_grid_head, read_metamap};
use super::reader::{grid_context, Reader};
use super::transform::read_transform;
use super::tree::read_grid_at;
use crate::error::{Result, VolumeError};

/// The oldest format that stores compression per grid and per-node mask
/// metadata; older files would need a second, rarely exercised code path.
const MIN_FILE_VERSION: u32 = 222;
/// The newest format we know (OpenVDB 12 added native half grids, which we
/// list as unsupported but otherwise read like 224).
const MAX_FILE_VERSION: u32 = 225;

/// What precedes the grid descriptors.
pub(super) struct Preamble {
    pub(super) version: u32,
    pub(super) has_offsets: bool,
    pub(super) count: usize,
    /// Offset of the first descriptor.
    pub(super) pos: usize,
}

/// Parses magic, version, flags, UUID, file metadata and the grid count.
/// `file_len` bounds the grid count when `r` holds only a window of the file.
pub(super) fn parse_preamble(r: &mut Reader, file_len: usize) -> Result<Preamble> {
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
pub(super) fn parse_descriptor(r: &mut Reader, i: usize) -> Result<(GridDesc, i64)> {
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

pub(super) fn parse_header(path: &Path, data: &[u8]) -> Result<FileHeader> {
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
            let end = match desc.components() {
                _ if !desc.instance_parent.is_empty() => {
                    read_grid_head(&mut r)?;
                    read_transform(&mut r)?;
                    r.offset()
                }
                Some(1) => read_grid_at::<1>(&mut r, &file, &desc)?.1,
                Some(3) => read_grid_at::<3>(&mut r, &file, &desc)?.1,
                _ => {
                    return Err(r.fail(format!(
                        "file has no grid offsets, so grid of type `{}` cannot be skipped",
                        desc.type_name
                    )))
                }
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

pub(super) fn check_offsets(r: &Reader, desc: &GridDesc, end: i64, len: usize) -> Result<()> {
    if end < 0 || desc.end_pos > len {
        return Err(r.fail(format!(
            "invalid grid offsets (grid {}, end {end}; file has {len} bytes)",
            desc.grid_pos
        )));
    }
    Ok(())
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
}

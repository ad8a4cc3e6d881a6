//! The file's structure around the grid buffers: segments (`io::Header`,
//! 16 B, then one `io::MetaData` of 176 B plus the grid's name per grid,
//! then the grids' bytes), or, from NanoVDB 32.6 on, raw grid buffers one
//! after another. Only these headers are read here; a grid's bytes are read
//! when it is chosen.

use std::borrow::Cow;
use std::path::Path;

use crate::error::{Result, VolumeError};

/// "NanoVDB0": files, and grids before 32.6.
pub(super) const MAGIC_NUMB: u64 = 0x3042_4456_6f6e_614e;
/// "NanoVDB1": grids from 32.6 on.
pub(super) const MAGIC_GRID: u64 = 0x3142_4456_6f6e_614e;
/// "NanoVDB2": files from 32.6 on.
const MAGIC_FILE: u64 = 0x3242_4456_6f6e_614e;
/// The ABI version this reader follows; other majors have other layouts.
pub(super) const MAJOR: u32 = 32;
const HEADER_LEN: usize = 16;
const META_LEN: usize = 176;
/// Longest grid name accepted in segment metadata (NanoVDB itself keeps
/// names over 255 bytes in blind data).
const MAX_NAME: usize = 1 << 16;
/// `GridData` is 672 bytes; its grid size, name, class and type are what a
/// raw buffer's listing needs.
pub(super) const GRID_DATA_LEN: usize = 672;

/// How a grid's bytes are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Codec {
    None,
    Zip,
    Blosc,
}

impl Codec {
    pub(super) fn name(self) -> &'static str {
        match self {
            Codec::None => "none",
            Codec::Zip => "zip",
            Codec::Blosc => "blosc",
        }
    }
}

/// One grid of the file, as its segment metadata (or raw `GridData`)
/// describes it.
#[derive(Debug, Clone)]
pub(super) struct GridEntry {
    pub(super) name: String,
    pub(super) grid_type: u32,
    pub(super) grid_class: u32,
    pub(super) version: u32,
    pub(super) codec: Codec,
    /// Bytes of the grid buffer once decoded.
    pub(super) grid_size: u64,
    /// Where its stored bytes start in the file, and how many there are.
    pub(super) data_pos: u64,
    pub(super) file_size: u64,
}

/// `major.minor.patch` of a packed NanoVDB version (`major << 21 | minor
/// << 10 | patch`), as [`VdbGrid::file_version`](crate::loaders::vdb::VdbGrid)
/// holds it for NanoVDB grids.
pub fn version_string(v: u32) -> String {
    format!("{}.{}.{}", v >> 21, (v >> 10) & 0x7ff, v & 0x3ff)
}

/// The file's bytes: in memory, or an open file read piece by piece.
pub(super) enum Source<'a> {
    Bytes(&'a [u8]),
    File(std::fs::File, u64),
}

impl<'a> Source<'a> {
    pub(super) fn len(&self) -> u64 {
        match self {
            Source::Bytes(b) => b.len() as u64,
            Source::File(_, len) => *len,
        }
    }

    /// `len` bytes at `pos`, which the caller has checked lie in the file.
    pub(super) fn read(&mut self, path: &Path, pos: u64, len: usize) -> Result<Cow<'a, [u8]>> {
        let end = pos.checked_add(len as u64).filter(|&e| e <= self.len());
        let Some(end) = end else {
            return Err(VolumeError::format(
                path,
                format!("read of {len} bytes at offset {pos} runs past the end of the file"),
            ));
        };
        match self {
            Source::Bytes(b) => Ok(Cow::Borrowed(&b[pos as usize..end as usize])),
            Source::File(f, _) => {
                use std::io::{Read, Seek, SeekFrom};
                f.seek(SeekFrom::Start(pos))
                    .map_err(|e| VolumeError::io(path, e))?;
                let mut buf = vec![0u8; len];
                f.read_exact(&mut buf)
                    .map_err(|e| VolumeError::io(path, e))?;
                Ok(Cow::Owned(buf))
            }
        }
    }
}

impl<'a> Source<'a> {
    /// A reader of the `len` bytes at `pos`, which must lie in the file.
    pub(super) fn reader<'s>(
        &'s mut self,
        path: &Path,
        pos: u64,
        len: usize,
    ) -> Result<Box<dyn std::io::Read + 's>> {
        let end = pos.checked_add(len as u64).filter(|&e| e <= self.len());
        if end.is_none() {
            return Err(VolumeError::format(
                path,
                format!("{len} bytes at offset {pos} run past the end of the file"),
            ));
        }
        match self {
            Source::Bytes(b) => Ok(Box::new(&b[pos as usize..pos as usize + len])),
            Source::File(f, _) => {
                use std::io::{Read, Seek, SeekFrom};
                f.seek(SeekFrom::Start(pos))
                    .map_err(|e| VolumeError::io(path, e))?;
                Ok(Box::new(std::io::BufReader::with_capacity(
                    1 << 16,
                    (&*f).take(len as u64),
                )))
            }
        }
    }
}

fn u16_at(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}
pub(super) fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}
pub(super) fn u64_at(b: &[u8], at: usize) -> u64 {
    let mut a = [0u8; 8];
    a.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(a)
}

/// Every grid of the file, segment files and raw grid buffers alike.
pub(super) fn parse_entries(path: &Path, src: &mut Source) -> Result<Vec<GridEntry>> {
    let len = src.len();
    if len < HEADER_LEN as u64 {
        return Err(VolumeError::format(
            path,
            format!("{len} bytes is too short for a NanoVDB file (16-byte header)"),
        ));
    }
    // The segment header, and a raw grid's version word after it.
    let head = src.read(path, 0, (HEADER_LEN + 4).min(len as usize))?;
    let magic = u64_at(&head, 0);
    if magic.swap_bytes() & 0x00ff_ffff_ffff_ffff == MAGIC_NUMB & 0x00ff_ffff_ffff_ffff {
        return Err(VolumeError::format(
            path,
            "NanoVDB file of the other byte order (big-endian) is not supported",
        ));
    }
    let major_at = |at: usize| head.len() >= at + 4 && u32_at(&head, at) >> 21 == MAJOR;
    match magic {
        MAGIC_GRID => parse_raw_grids(path, src),
        MAGIC_FILE => parse_segments(path, src),
        MAGIC_NUMB if !major_at(8) && major_at(16) => parse_raw_grids(path, src),
        MAGIC_NUMB => parse_segments(path, src).or_else(|e| {
            // Ambiguous only when the raw grid's checksum happens to look
            // like a version; the raw reading decides then.
            if major_at(16) {
                parse_raw_grids(path, src).map_err(|_| e)
            } else {
                Err(e)
            }
        }),
        _ => Err(VolumeError::format(
            path,
            format!(
                "not a NanoVDB file: magic {:?} at offset 0 (expected \"NanoVDB0\")",
                String::from_utf8_lossy(&head[..8])
            ),
        )),
    }
}

/// A version word's major must be 32; the message names what was found.
fn check_version(path: &Path, version: u32, what: &str, at: u64) -> Result<()> {
    if version >> 21 == MAJOR {
        return Ok(());
    }
    Err(VolumeError::format(
        path,
        format!(
            "{what} at offset {at} has NanoVDB version {} (major {}); only major version {MAJOR} can be read",
            version_string(version),
            version >> 21
        ),
    ))
}

fn parse_segments(path: &Path, src: &mut Source) -> Result<Vec<GridEntry>> {
    let len = src.len();
    let mut pos = 0u64;
    let mut out = Vec::new();
    while pos < len {
        if len - pos < HEADER_LEN as u64 {
            return Err(VolumeError::format(
                path,
                format!(
                    "truncated segment header at offset {pos} ({} bytes left)",
                    len - pos
                ),
            ));
        }
        let head = src.read(path, pos, HEADER_LEN)?;
        let magic = u64_at(&head, 0);
        if magic != MAGIC_NUMB && magic != MAGIC_FILE {
            return Err(VolumeError::format(
                path,
                format!("bad segment magic {magic:#018x} at offset {pos} (expected \"NanoVDB0\")"),
            ));
        }
        let version = u32_at(&head, 8);
        check_version(path, version, "segment", pos)?;
        let count = u16_at(&head, 12) as usize;
        let codec = match u16_at(&head, 14) {
            0 => Codec::None,
            1 => Codec::Zip,
            2 => Codec::Blosc,
            c => {
                return Err(VolumeError::format(
                    path,
                    format!("unknown codec {c} in segment header at offset {pos}"),
                ))
            }
        };
        pos += HEADER_LEN as u64;
        let first = out.len();
        for _ in 0..count {
            let (entry, next) = parse_meta(path, src, pos, version, codec)?;
            out.push(entry);
            pos = next;
        }
        // The grids' bytes follow all of the segment's metadata, in order.
        for e in &mut out[first..] {
            e.data_pos = pos;
            pos = pos
                .checked_add(e.file_size)
                .filter(|&end| end <= len)
                .ok_or_else(|| {
                    VolumeError::format(
                        path,
                        format!(
                            "grid `{}` claims {} stored bytes at offset {pos} but the file has {len}",
                            e.name, e.file_size
                        ),
                    )
                })?;
        }
    }
    Ok(out)
}

/// One `io::MetaData` record and its name at `pos`; returns the entry and
/// the offset after the name.
fn parse_meta(
    path: &Path,
    src: &mut Source,
    pos: u64,
    version: u32,
    codec: Codec,
) -> Result<(GridEntry, u64)> {
    let len = src.len();
    if len - pos < META_LEN as u64 {
        return Err(VolumeError::format(
            path,
            format!(
                "truncated grid metadata at offset {pos} ({} bytes left)",
                len - pos
            ),
        ));
    }
    let m = src.read(path, pos, META_LEN)?;
    let name_size = u32_at(&m, 136) as usize;
    let name_pos = pos + META_LEN as u64;
    if name_size > MAX_NAME || name_size as u64 > len - name_pos {
        return Err(VolumeError::format(
            path,
            format!("grid metadata at offset {pos} claims a {name_size}-byte name"),
        ));
    }
    let raw = src.read(path, name_pos, name_size)?;
    let name_end = raw.iter().position(|&b| b == 0).unwrap_or(raw.len());
    let entry = GridEntry {
        name: String::from_utf8_lossy(&raw[..name_end]).into_owned(),
        grid_type: u32_at(&m, 32),
        grid_class: u32_at(&m, 36),
        version,
        codec,
        grid_size: u64_at(&m, 0),
        data_pos: 0,
        file_size: u64_at(&m, 8),
    };
    Ok((entry, name_pos + name_size as u64))
}

/// Grid buffers stored one after another without segment headers: each
/// `GridData` gives its own size, name, class and type.
fn parse_raw_grids(path: &Path, src: &mut Source) -> Result<Vec<GridEntry>> {
    let len = src.len();
    let mut pos = 0u64;
    let mut out = Vec::new();
    while pos < len {
        if len - pos < GRID_DATA_LEN as u64 {
            return Err(VolumeError::format(
                path,
                format!(
                    "truncated grid header at offset {pos} ({} bytes left)",
                    len - pos
                ),
            ));
        }
        let g = src.read(path, pos, GRID_DATA_LEN)?;
        let magic = u64_at(&g, 0);
        if magic != MAGIC_NUMB && magic != MAGIC_GRID {
            return Err(VolumeError::format(
                path,
                format!("bad grid magic {magic:#018x} at offset {pos} (expected \"NanoVDB1\")"),
            ));
        }
        let version = u32_at(&g, 16);
        check_version(path, version, "grid", pos)?;
        let size = u64_at(&g, 32);
        if size < GRID_DATA_LEN as u64 || size > len - pos {
            return Err(VolumeError::format(
                path,
                format!(
                    "grid at offset {pos} claims {size} bytes but {} remain",
                    len - pos
                ),
            ));
        }
        let name = &g[40..296];
        let name_end = name.iter().position(|&b| b == 0).unwrap_or(name.len());
        out.push(GridEntry {
            name: String::from_utf8_lossy(&name[..name_end]).into_owned(),
            grid_type: u32_at(&g, 636),
            grid_class: u32_at(&g, 632),
            version,
            codec: Codec::None,
            grid_size: size,
            data_pos: pos,
            file_size: size,
        });
        pos += size;
    }
    Ok(out)
}

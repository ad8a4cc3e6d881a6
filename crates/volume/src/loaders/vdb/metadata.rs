//! Metadata maps and the grid header: compression flags and grid class.

use super::format::{COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC, COMPRESS_ZIP};
use super::grid::GridClass;
use super::reader::Reader;
use crate::error::Result;

/// Reads a metadata map and returns `(name, type, raw value)` entries.
pub(super) fn read_metamap<'a>(r: &mut Reader<'a>) -> Result<Vec<(String, String, &'a [u8])>> {
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

pub(super) struct GridHead {
    pub(super) compression: u32,
    pub(super) class: GridClass,
}

pub(super) fn read_grid_head(r: &mut Reader) -> Result<GridHead> {
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

pub(super) fn compression_name(c: u32) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compression_names() {
        assert_eq!(compression_name(0), "none");
        assert_eq!(compression_name(6), "blosc + active-mask");
        assert_eq!(compression_name(3), "zip + active-mask");
    }
}

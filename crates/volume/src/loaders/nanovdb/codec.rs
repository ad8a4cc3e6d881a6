//! A grid's stored bytes → its grid buffer (`io::Internal::read`): raw;
//! ZIP, a `u64` compressed size and one zlib stream of the whole buffer;
//! BLOSC, the buffer cut into chunks of at most 2³⁰ bytes, each stored as a
//! `u64` compressed size and one Blosc1 frame.

use std::borrow::Cow;
use std::io::Read;
use std::path::Path;

use super::segment::{u64_at, Codec, GridEntry};
use crate::error::{Result, VolumeError};
use crate::loaders::vdb::blosc;

/// NanoVDB cuts Blosc input into chunks of this size.
const BLOSC_CHUNK: u64 = 1 << 30;
/// No codec that Blosc or zlib use expands data more than this (zlib's
/// limit is about 1032:1), so a frame or stream claiming more is corrupt
/// and is rejected before its output is allocated.
const MAX_RATIO: u64 = 1100;

/// The grid buffer of `e` from its stored bytes `data` (which start at file
/// offset `e.data_pos`).
pub(super) fn decode<'a>(path: &Path, e: &GridEntry, data: Cow<'a, [u8]>) -> Result<Cow<'a, [u8]>> {
    let fail = |at: u64, msg: String| {
        VolumeError::format(
            path,
            format!("{msg} in grid `{}` at offset {}", e.name, e.data_pos + at),
        )
    };
    match e.codec {
        Codec::None => {
            if e.grid_size != data.len() as u64 {
                return Err(fail(
                    0,
                    format!(
                        "uncompressed grid of {} stored bytes declares a {}-byte buffer",
                        data.len(),
                        e.grid_size
                    ),
                ));
            }
            Ok(data)
        }
        Codec::Zip => unzip(&data, e.grid_size)
            .map(Cow::Owned)
            .map_err(|(at, m)| fail(at, m)),
        Codec::Blosc => unblosc(&data, e.grid_size)
            .map(Cow::Owned)
            .map_err(|(at, m)| fail(at, m)),
    }
}

type Failure = (u64, String);

/// The `u64`-size-prefixed block at `at`: its payload, and the offset after it.
fn sized_block(data: &[u8], at: usize, what: &str) -> std::result::Result<(usize, usize), Failure> {
    if data.len() - at < 8 {
        return Err((at as u64, format!("truncated {what} size")));
    }
    let size = u64_at(data, at);
    let start = at + 8;
    if size > (data.len() - start) as u64 {
        return Err((
            at as u64,
            format!(
                "{what} claims {size} bytes but {} remain",
                data.len() - start
            ),
        ));
    }
    Ok((start, start + size as usize))
}

fn too_large(size: u64, stored: usize) -> Option<Failure> {
    (size
        > (stored as u64)
            .saturating_mul(MAX_RATIO)
            .saturating_add(4096))
    .then(|| {
        (
            0,
            format!("{stored} compressed bytes cannot hold the declared {size}-byte grid buffer"),
        )
    })
}

fn unzip(data: &[u8], size: u64) -> std::result::Result<Vec<u8>, Failure> {
    let (start, end) = sized_block(data, 0, "ZIP stream")?;
    if let Some(f) = too_large(size, end - start) {
        return Err(f);
    }
    let mut out = Vec::new();
    // One byte more than declared, to tell a stream that is too long.
    flate2::read::ZlibDecoder::new(&data[start..end])
        .take(size.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| (start as u64, format!("corrupt ZIP stream: {e}")))?;
    if out.len() as u64 != size {
        return Err((
            start as u64,
            format!(
                "ZIP stream holds {}{} bytes, the metadata declares {size}",
                out.len().min(size as usize),
                if out.len() as u64 > size { "+" } else { "" }
            ),
        ));
    }
    Ok(out)
}

fn unblosc(data: &[u8], size: u64) -> std::result::Result<Vec<u8>, Failure> {
    let mut out = Vec::new();
    let mut at = 0usize;
    let mut residual = size;
    while residual > 0 {
        let (start, end) = sized_block(data, at, "BLOSC chunk")?;
        let chunk = residual.min(BLOSC_CHUNK);
        if let Some((_, m)) = too_large(chunk, end - start) {
            return Err((at as u64, m));
        }
        let bytes = blosc::decompress(&data[start..end], chunk as usize)
            .map_err(|e| (start as u64, format!("corrupt BLOSC chunk: {e}")))?;
        if out.is_empty() {
            out = bytes;
        } else {
            out.extend_from_slice(&bytes);
        }
        residual -= chunk;
        at = end;
    }
    if at != data.len() {
        return Err((
            at as u64,
            format!("{} bytes after the last BLOSC chunk", data.len() - at),
        ));
    }
    Ok(out)
}

//! Node value buffers: active-mask compression, half floats, Zip and Blosc
//! chunks.

use super::blosc;
use super::grid::bit_on;
use super::metadata::{COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC, COMPRESS_ZIP};
use super::reader::Reader;
use crate::error::Result;

/// What node buffers need to know to decode: the stream settings OpenVDB
/// keeps on its `istream`.
pub(super) struct Codec {
    pub(super) compression: u32,
    pub(super) half: bool,
    pub(super) background: f32,
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
pub(super) fn read_compressed_values(
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
        let produced = blosc::inflate(src, &mut out)
            .map_err(|e| r.fail_at(at, format!("{what}: corrupt zlib data ({e})")))?;
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

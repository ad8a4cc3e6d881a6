//! Node value buffers: active-mask compression, half floats, Zip and Blosc
//! chunks, for values of one float (`float` grids) or three (`vec3s`).

use super::blosc;
use super::format::{COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC, COMPRESS_ZIP};
use super::format::{MASK_AND_NO_INACTIVE_VALS, MASK_AND_ONE_INACTIVE_VAL};
use super::format::{MASK_AND_TWO_INACTIVE_VALS, NO_MASK_AND_ALL_VALS, NO_MASK_AND_MINUS_BG};
use super::format::{NO_MASK_AND_ONE_INACTIVE_VAL, NO_MASK_OR_INACTIVE_VALS};
use super::grid::bit_on;
use super::reader::Reader;
use crate::error::Result;

/// What node buffers need to know to decode: the stream settings OpenVDB
/// keeps on its `istream`. `K` is the number of floats per value: 1 for
/// `float` grids, 3 for `vec3s` grids.
pub(super) struct Codec<const K: usize> {
    pub(super) compression: u32,
    pub(super) half: bool,
    pub(super) background: [f32; K],
}

/// Fills `out` (one value of `K` floats, interleaved, per bit of
/// `value_mask`) from a node buffer that may hold only the active values, in
/// half or full precision, raw, Zip or Blosc compressed. Inactive values are
/// rebuilt from the background, the stored inactive values and the
/// selection mask.
pub(super) fn read_compressed_values<const K: usize>(
    r: &mut Reader,
    codec: &Codec<K>,
    out: &mut [f32],
    value_mask: &[u64],
    what: &str,
) -> Result<()> {
    let n = out.len() / K;
    let at = r.offset();
    let meta = r.u8("node compression metadata")?;
    if meta > NO_MASK_AND_ALL_VALS {
        return Err(r.fail_at(
            at,
            format!("invalid compression metadata byte {meta} for {what}"),
        ));
    }
    let bg = codec.background;
    // OpenVDB negates vectors component by component.
    let mut inactive0 = match meta {
        NO_MASK_OR_INACTIVE_VALS => bg,
        NO_MASK_AND_MINUS_BG | MASK_AND_NO_INACTIVE_VALS => bg.map(|v| -v),
        // Replaced below by the stored value; OpenVDB starts from -background too.
        _ => bg.map(|v| -v),
    };
    let mut inactive1 = bg;
    if matches!(
        meta,
        NO_MASK_AND_ONE_INACTIVE_VAL | MASK_AND_ONE_INACTIVE_VAL | MASK_AND_TWO_INACTIVE_VALS
    ) {
        // Always `sizeof(ValueType)` bytes, even in half-float grids (whose
        // writer rounds the value to half precision but stores it full).
        inactive0 = read_full(r, "inactive value")?;
        if meta == MASK_AND_TWO_INACTIVE_VALS {
            inactive1 = read_full(r, "inactive value")?;
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
    let values = read_values(r, codec, count * K, what)?;
    if count == n {
        out.copy_from_slice(&values);
    } else {
        let mut next = values.chunks_exact(K);
        for (idx, slot) in out.chunks_exact_mut(K).enumerate() {
            slot.copy_from_slice(if bit_on(value_mask, idx) {
                // `count` equals the number of set bits, so this never runs dry.
                next.next().unwrap_or(&bg[..])
            } else if selection.as_ref().is_some_and(|s| bit_on(s, idx)) {
                &inactive1[..]
            } else {
                &inactive0[..]
            });
        }
    }
    Ok(())
}

/// One value of `K` full-precision floats.
pub(super) fn read_full<const K: usize>(r: &mut Reader, what: &str) -> Result<[f32; K]> {
    let mut v = [0.0f32; K];
    for c in v.iter_mut() {
        *c = r.f32(what)?;
    }
    Ok(v)
}

/// Reads `floats` floats (values times components), as half or full
/// precision, through the grid's codec.
fn read_values<const K: usize>(
    r: &mut Reader,
    codec: &Codec<K>,
    floats: usize,
    what: &str,
) -> Result<Vec<f32>> {
    if codec.half {
        // OpenVDB writes nothing at all, not even a size, for empty half buffers.
        if floats == 0 {
            return Ok(Vec::new());
        }
        let bytes = read_chunk(r, codec.compression, floats * 2, what)?;
        Ok(bytes
            .chunks_exact(2)
            .map(|c| half::f16::from_bits(u16::from_le_bytes([c[0], c[1]])).to_f32())
            .collect())
    } else {
        let bytes = read_chunk(r, codec.compression, floats * 4, what)?;
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
    compression: u32,
    nbytes: usize,
    what: &str,
) -> Result<std::borrow::Cow<'a, [u8]>> {
    use std::borrow::Cow;
    let blosc = compression & COMPRESS_BLOSC != 0;
    let zip = compression & COMPRESS_ZIP != 0;
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

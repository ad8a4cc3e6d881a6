//! Leaf values. Every leaf stores all 512 values, active or not, with voxel
//! `(x, y, z)` of the leaf at index `x·64 + y·8 + z` (OpenVDB's order too).
//! Full-precision leaves hold the values themselves; quantised leaves hold
//! a minimum and a quantum (f32) and one code per voxel, and the value is
//! `code · quantum + minimum` computed in f32 exactly as NanoVDB's
//! `getValue` does: Fp4 packs two codes per byte (low nibble first), Fp8
//! and Fp16 one u8 or u16 each, and FpN `1 << (flags >> 5)` bits each,
//! least significant first, in a leaf of `96 + 64 · bits` bytes.

use super::gridbuf::GridBuf;
use super::layout::{Layout, ValueKind, FP_CODES, FP_MINIMUM, FP_QUANTUM};
use crate::error::Result;

/// Byte offset of the leaf flags (after the origin and the bbox extent).
const LEAF_FLAGS: usize = 15;

/// The code width of the FpN leaf at `at`, from its flags.
pub(super) fn fpn_bits(b: &GridBuf, at: usize) -> Result<u32> {
    let flags = b.u8(at + LEAF_FLAGS, "FpN leaf flags")?;
    let log2 = flags >> 5;
    if log2 > 4 {
        return Err(b.fail(
            at + LEAF_FLAGS,
            format!("FpN leaf flags {flags:#04x} give a code width of 2^{log2} bits (at most 16)"),
        ));
    }
    Ok(1 << log2)
}

/// The leaf's 512 values (`K` floats each, component fastest) into `out`.
pub(super) fn read_values(b: &GridBuf, lay: &Layout, at: usize, out: &mut [f32]) -> Result<()> {
    let n = out.len();
    match lay.kind {
        ValueKind::Float | ValueKind::Vec3f => {
            let s = b.bytes(at + lay.leaf_values, n * 4, "leaf values")?;
            for (v, c) in out.iter_mut().zip(s.chunks_exact(4)) {
                *v = f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
            }
        }
        ValueKind::Double | ValueKind::Vec3d => {
            let s = b.bytes(at + lay.leaf_values, n * 8, "leaf values")?;
            for (v, c) in out.iter_mut().zip(s.chunks_exact(8)) {
                let mut a = [0u8; 8];
                a.copy_from_slice(c);
                *v = f64::from_le_bytes(a) as f32;
            }
        }
        kind => {
            let bits = match kind.code_bits() {
                Some(bits) => bits,
                None => fpn_bits(b, at)?,
            };
            dequantise(b, at, bits, out)?;
        }
    }
    Ok(())
}

/// Codes of `bits` bits (1, 2, 4, 8 or 16), least significant first, as
/// `code · quantum + minimum`.
fn dequantise(b: &GridBuf, at: usize, bits: u32, out: &mut [f32]) -> Result<()> {
    let minimum = b.f32(at + FP_MINIMUM, "leaf minimum")?;
    let quantum = b.f32(at + FP_QUANTUM, "leaf quantum")?;
    let codes = b.bytes(at + FP_CODES, 64 * bits as usize, "leaf codes")?;
    for (i, v) in out.iter_mut().enumerate() {
        let code = if bits == 16 {
            u16::from_le_bytes([codes[2 * i], codes[2 * i + 1]]) as u32
        } else {
            let per_byte = 8 / bits as usize;
            let shift = (i % per_byte) as u32 * bits;
            (codes[i / per_byte] as u32 >> shift) & ((1 << bits) - 1)
        };
        *v = code as f32 * quantum + minimum;
    }
    Ok(())
}

//! The leaves, read as the grid buffer streams past: in buffer order, a run
//! of consecutive leaves at a time, each run's leaves decoded (and handed
//! to the caller's `make`) in parallel, then kept in buffer order. A leaf
//! costs memory only while its run is being decoded.

use rayon::prelude::*;

use super::gridbuf::GridBuf;
use super::layout::{Layout, ValueKind, FP_CODES, LEAF_MASK};
use super::leaf::{fpn_bits, read_values};
use super::stream::GridStream;
use super::tree::LeafAt;
use crate::error::Result;

/// Bytes of leaves decoded together (a few thousand leaves).
const RUN_BYTES: usize = 4 << 20;

/// One leaf's values: 512 values of `K` floats (component fastest), voxel
/// `(x, y, z)` at `x·64 + y·8 + z`.
pub(super) struct LeafValues {
    pub(super) origin: [i32; 3],
    pub(super) active: [u64; 8],
    pub(super) values: Vec<f32>,
}

/// A leaf's bytes within the current run.
struct Placed {
    /// Its index in the walk's order.
    index: usize,
    at: usize,
    start: usize,
    size: usize,
}

/// Reads every leaf of `leaves` from `stream` (which must stand before the
/// first), calls `make(index, values)` for each (in parallel within a run)
/// and `keep(index, made)` in buffer order. `index` is the leaf's place in
/// `leaves`. With `crcs`, each leaf's CRC32 (over its struct, as the
/// checksum counts it) is appended in buffer order.
pub(super) fn stream_leaves<const K: usize, R: Send>(
    stream: &mut GridStream,
    b: &GridBuf,
    lay: &Layout,
    leaves: &[LeafAt],
    mut crcs: Option<&mut Vec<u32>>,
    make: impl Fn(usize, LeafValues) -> R + Sync,
    mut keep: impl FnMut(usize, R) -> Result<()>,
) -> Result<()> {
    let mut order: Vec<usize> = (0..leaves.len()).collect();
    order.sort_unstable_by_key(|&i| leaves[i].at);
    let mut run = Vec::new();
    let mut placed = Vec::new();
    for (n, &index) in order.iter().enumerate() {
        let at = leaves[index].at;
        if at < stream.pos() {
            return Err(b.fail(at, "leaf overlaps the node before it"));
        }
        // Leaves are usually back to back; what lies between is skipped.
        stream.skip_to(at)?;
        let start = run.len();
        stream.read_into(&mut run, lay.leaf_size)?;
        let mut size = lay.leaf_size;
        if lay.kind == ValueKind::FpN {
            let head = b.window(&run[start..], at);
            let codes = 64 * fpn_bits(&head, at)? as usize;
            stream.read_into(&mut run, codes)?;
            size += codes;
        }
        placed.push(Placed {
            index,
            at,
            start,
            size,
        });
        if run.len() >= RUN_BYTES || n + 1 == order.len() {
            flush::<K, R>(
                b,
                lay,
                leaves,
                &mut run,
                &mut placed,
                &mut crcs,
                &make,
                &mut keep,
            )?;
        }
    }
    Ok(())
}

/// Decodes the run's leaves in parallel and keeps them in order.
#[allow(clippy::too_many_arguments)]
fn flush<const K: usize, R: Send>(
    b: &GridBuf,
    lay: &Layout,
    leaves: &[LeafAt],
    run: &mut Vec<u8>,
    placed: &mut Vec<Placed>,
    crcs: &mut Option<&mut Vec<u32>>,
    make: &(impl Fn(usize, LeafValues) -> R + Sync),
    keep: &mut impl FnMut(usize, R) -> Result<()>,
) -> Result<()> {
    let want_crc = crcs.is_some();
    let made: Vec<(u32, usize, R)> = placed
        .par_iter()
        .map(|p| {
            let w = b.window(&run[p.start..p.start + p.size], p.at);
            let mask = w.mask(p.at + LEAF_MASK, 8, "leaf value mask")?;
            let mut values = vec![0.0f32; 512 * K];
            read_values(&w, lay, p.at, &mut values)?;
            // The checksum counts an FpN leaf's struct, without its codes.
            let crc = if want_crc {
                let n = if lay.kind == ValueKind::FpN {
                    FP_CODES
                } else {
                    p.size
                };
                crc32(w.bytes(p.at, n, "checksummed leaf")?)
            } else {
                0
            };
            let leaf = LeafValues {
                origin: leaves[p.index].origin,
                active: std::array::from_fn(|i| mask[i]),
                values,
            };
            Ok((crc, p.index, make(p.index, leaf)))
        })
        .collect::<Result<_>>()?;
    run.clear();
    placed.clear();
    for (crc, index, r) in made {
        if let Some(c) = crcs.as_deref_mut() {
            c.push(crc);
        }
        keep(index, r)?;
    }
    Ok(())
}

pub(super) fn crc32(bytes: &[u8]) -> u32 {
    let mut c = flate2::Crc::new();
    c.update(bytes);
    c.sum()
}

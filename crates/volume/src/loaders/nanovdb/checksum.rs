//! The grid checksum of NanoVDB 32.4 (`util/GridChecksum.h`): two CRC32s
//! (the common reflected polynomial 0xEDB88320, as zlib's) packed in a
//! `u64`, the head's in the low half and the nodes' in the high half; all
//! ones in a half means "not computed".
//!
//! - head: the bytes from offset 16 (after magic and checksum) to the end
//!   of the root's tile table, counted as `GridData` + `TreeData` + root
//!   node + tiles from the buffer start;
//! - nodes: one CRC32 per node, over the node's struct (`sizeof`, which
//!   for FpN leaves is the 96-byte header without the codes), upper nodes
//!   first, then lower nodes, then leaves, each level in memory order; then
//!   one CRC32 over that list stored as 8-byte words (`std::uint_fast32_t`
//!   of the 64-bit Linux build that writes these files).
//!
//! The layout of the checksum changed after 32.4, so grids of other minor
//! versions are not checked.

use super::gridbuf::GridBuf;
use super::griddata::GridHead;
use super::layout::Layout;
use super::leaves::crc32;
use super::tree::Flat;
use crate::error::Result;

const EMPTY: u32 = u32::MAX;
/// The only minor version whose checksum was confirmed against its source.
const CHECKED_MINOR: u32 = 4;

/// Whether the grid's checksum can be and is to be verified.
pub(super) fn applies(head: &GridHead) -> bool {
    (head.version >> 10) & 0x7ff == CHECKED_MINOR && head.checksum != u64::MAX
}

/// Checks the stored checksum of the grid whose internal nodes `b` holds,
/// whose tree is `flat` and whose leaves' CRC32s, in buffer order, are
/// `leaf_crcs`.
pub(super) fn verify<const K: usize>(
    b: &GridBuf,
    head: &GridHead,
    flat: &Flat<K>,
    leaf_crcs: &[u32],
) -> Result<()> {
    if !applies(head) {
        return Ok(());
    }
    let stored = [head.checksum as u32, (head.checksum >> 32) as u32];
    let lay = Layout::new(head.kind);
    let root = head.node_offset[3];
    let table = b.u32(root + 24, "root table size")? as usize;
    let head_end = 672 + 64 + lay.root_size + table * lay.tile_size;
    let head_crc = crc32(b.bytes(16, head_end.saturating_sub(16), "checksummed grid head")?);
    if stored[0] != EMPTY && stored[0] != head_crc {
        return Err(b.fail(
            8,
            format!(
                "checksum mismatch: the head's CRC32 is {head_crc:#010x}, the grid stores {:#010x}",
                stored[0]
            ),
        ));
    }
    if stored[1] == EMPTY {
        return Ok(());
    }
    let mut list = Vec::new();
    for nodes in &flat.nodes {
        let mut nodes = nodes.clone();
        nodes.sort_unstable();
        for (at, size) in nodes {
            let crc = crc32(b.bytes(at, size, "checksummed node")?);
            list.extend_from_slice(&(crc as u64).to_le_bytes());
        }
    }
    for &crc in leaf_crcs {
        list.extend_from_slice(&(crc as u64).to_le_bytes());
    }
    let nodes_crc = crc32(&list);
    if stored[1] != nodes_crc {
        return Err(b.fail(
            8,
            format!(
                "checksum mismatch: the nodes' CRC32 is {nodes_crc:#010x}, the grid stores {:#010x}",
                stored[1]
            ),
        ));
    }
    Ok(())
}

//! Decoder for Blosc1 frames as OpenVDB writes them (one frame per node
//! buffer). Written from the c-blosc frame description rather than bound to
//! the C library so that a malformed frame can only ever produce an error.
//!
//! The frame is: a 16-byte header (format version, codec version, flags,
//! type size, uncompressed size, block size, compressed size), then, unless
//! the frame is a plain copy, one `i32` start offset per block; each block
//! holds one or `typesize` "splits", each prefixed with its compressed size
//! (equal to the split size when the codec could not shrink it). Blocks are
//! byte- or bit-shuffled before compression.

use std::fmt;

// The frame format's constants, shared with the encoder
// (`crate::writers::compress`).
pub(crate) const HEADER_LEN: usize = 16;
pub(crate) const FLAG_SHUFFLE: u8 = 0x1;
pub(crate) const FLAG_MEMCPYED: u8 = 0x2;
const FLAG_BITSHUFFLE: u8 = 0x4;
const FLAG_RESERVED: u8 = 0x8;
pub(crate) const FLAG_DONT_SPLIT: u8 = 0x10;
/// c-blosc only splits blocks whose type size is at most this...
const MAX_SPLITS: usize = 16;
/// ...and that hold at least this many elements; older writers did not
/// record the split decision, so the reader has to recompute it.
const MIN_BUFFERSIZE: usize = 128;

/// Why a frame could not be decoded. Kept small and textual; the caller adds
/// file, grid and offset.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BloscError(pub String);

impl fmt::Display for BloscError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

fn err<T>(msg: impl Into<String>) -> Result<T, BloscError> {
    Err(BloscError(msg.into()))
}

fn read_u32(b: &[u8], at: usize) -> Option<u32> {
    let s = b.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
}

/// A Blosc frame's 16-byte header, checked against the frame's length and
/// the payload size the caller expects.
struct FrameHeader {
    flags: u8,
    typesize: usize,
    nbytes: usize,
    blocksize: usize,
    cbytes: usize,
}

impl FrameHeader {
    /// The header at the start of `src`, of a frame of `frame_len` bytes;
    /// `None` for an empty payload.
    fn parse(
        src: &[u8],
        frame_len: usize,
        expected: usize,
    ) -> Result<Option<FrameHeader>, BloscError> {
        if src.len() < HEADER_LEN || frame_len < HEADER_LEN {
            return err(format!(
                "Blosc frame of {frame_len} bytes is shorter than its 16-byte header"
            ));
        }
        let version = src[0];
        let flags = src[2];
        let typesize = src[3] as usize;
        let nbytes = read_u32(src, 4).unwrap_or(0) as usize;
        let blocksize = read_u32(src, 8).unwrap_or(0) as usize;
        let cbytes = read_u32(src, 12).unwrap_or(0) as usize;

        if nbytes != expected {
            return err(format!(
                "Blosc frame holds {nbytes} bytes, expected {expected}"
            ));
        }
        if nbytes == 0 {
            return Ok(None);
        }
        if version != 2 {
            return err(format!(
                "unsupported Blosc format version {version} (expected 2)"
            ));
        }
        if flags & FLAG_RESERVED != 0 {
            return err(format!("Blosc frame has unknown flags {flags:#04x}"));
        }
        if typesize == 0 {
            return err("Blosc frame has type size 0");
        }
        if blocksize == 0 || blocksize > nbytes.max(1) || blocksize > i32::MAX as usize {
            return err(format!(
                "Blosc frame has invalid block size {blocksize} for {nbytes} bytes"
            ));
        }
        if cbytes < HEADER_LEN || cbytes > frame_len {
            return err(format!(
                "Blosc frame claims {cbytes} compressed bytes but {frame_len} are available"
            ));
        }
        Ok(Some(FrameHeader {
            flags,
            typesize,
            nbytes,
            blocksize,
            cbytes,
        }))
    }
}

/// Decompresses one frame whose payload must be exactly `expected` bytes;
/// the caller knows the size a node needs, so a frame claiming any other
/// size is rejected before anything is allocated from its header.
pub fn decompress(src: &[u8], expected: usize) -> Result<Vec<u8>, BloscError> {
    let Some(mut frame) = FrameStream::parse(src, src.len(), expected)? else {
        return Ok(Vec::new());
    };
    let src = &src[..frame.cbytes];
    frame.set_offsets(&src[HEADER_LEN..HEADER_LEN + frame.offsets_len()], false)?;
    let mut out = vec![0u8; expected];
    let mut tmp = vec![0u8; frame.block_size()];
    for j in 0..frame.blocks() {
        // A block's splits delimit themselves: it may run to the frame's end.
        let bytes = match frame.format {
            Some(_) => frame.starts[j]..frame.cbytes,
            None => frame.block_bytes(j),
        };
        let at = j * frame.blocksize;
        let len = frame.block_len(j);
        frame.decode_block(j, &src[bytes], &mut out[at..at + len], &mut tmp)?;
    }
    Ok(out)
}

/// A frame read front to back, for readers that do not hold it: its
/// header, then its block offsets, then each block's bytes in turn (which
/// must follow one another, as c-blosc writes them).
pub struct FrameStream {
    nbytes: usize,
    blocksize: usize,
    cbytes: usize,
    /// `None` for a frame stored as a plain copy.
    format: Option<BlockFormat>,
    starts: Vec<usize>,
}

impl FrameStream {
    /// The frame whose first 16 bytes are `head`, stored in `stored`
    /// bytes, whose payload must be `expected` bytes; `None` for an empty
    /// payload.
    pub fn parse(
        head: &[u8],
        stored: usize,
        expected: usize,
    ) -> Result<Option<FrameStream>, BloscError> {
        let Some(h) = FrameHeader::parse(head, stored, expected)? else {
            return Ok(None);
        };
        let nblocks = h.nbytes.div_ceil(h.blocksize);
        let format = if h.flags & FLAG_MEMCPYED != 0 {
            if h.cbytes != h.nbytes + HEADER_LEN {
                return err(format!(
                    "uncompressed Blosc frame has {} bytes, expected {}",
                    h.cbytes,
                    h.nbytes + HEADER_LEN
                ));
            }
            None
        } else {
            if nblocks > (h.cbytes - HEADER_LEN) / 4 {
                return err(format!(
                    "Blosc frame too short for its {nblocks} block offsets"
                ));
            }
            Some(BlockFormat {
                flags: h.flags,
                typesize: h.typesize,
                codec: Codec::from_flags(h.flags)?,
            })
        };
        Ok(Some(FrameStream {
            nbytes: h.nbytes,
            blocksize: h.blocksize,
            cbytes: h.cbytes,
            format,
            starts: Vec::new(),
        }))
    }

    /// Bytes of block offsets after the header (none for a plain copy).
    pub fn offsets_len(&self) -> usize {
        match self.format {
            Some(_) => 4 * self.blocks(),
            None => 0,
        }
    }

    /// Reads the block offsets (`offsets_len` bytes), which must lie
    /// inside the frame and, when the blocks are to be read in turn
    /// (`increasing`), after the offsets and each after the one before.
    pub fn set_offsets(&mut self, b: &[u8], increasing: bool) -> Result<(), BloscError> {
        let mut last = HEADER_LEN + self.offsets_len();
        self.starts = Vec::with_capacity(self.blocks());
        for (j, c) in b.chunks_exact(4).enumerate() {
            let s = u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize;
            if s >= self.cbytes || (increasing && s < last) {
                return err(format!(
                    "Blosc block {j} starts at byte {s}, {} the {}-byte frame",
                    if increasing {
                        format!("not after byte {last} inside")
                    } else {
                        "outside".to_string()
                    },
                    self.cbytes
                ));
            }
            self.starts.push(s);
            last = s + 1;
        }
        Ok(())
    }

    pub fn blocks(&self) -> usize {
        self.nbytes.div_ceil(self.blocksize)
    }

    pub fn block_size(&self) -> usize {
        self.blocksize
    }

    /// The frame's compressed size (bytes after it in its chunk are unused).
    pub fn cbytes(&self) -> usize {
        self.cbytes
    }

    /// Block `j`'s length in the payload.
    pub fn block_len(&self, j: usize) -> usize {
        self.blocksize.min(self.nbytes - j * self.blocksize)
    }

    /// Where block `j`'s stored bytes lie in the frame.
    pub fn block_bytes(&self, j: usize) -> std::ops::Range<usize> {
        match self.format {
            None => {
                let at = HEADER_LEN + j * self.blocksize;
                at..at + self.block_len(j)
            }
            Some(_) => self.starts[j]..self.starts.get(j + 1).copied().unwrap_or(self.cbytes),
        }
    }

    /// Decodes block `j` from its stored bytes `bytes` ([`Self::block_bytes`])
    /// into `dest` ([`Self::block_len`] bytes), with `tmp` of at least
    /// [`Self::block_size`] bytes as scratch.
    pub fn decode_block(
        &self,
        j: usize,
        bytes: &[u8],
        dest: &mut [u8],
        tmp: &mut [u8],
    ) -> Result<(), BloscError> {
        let Some(format) = &self.format else {
            dest.copy_from_slice(bytes);
            return Ok(());
        };
        let is_leftover = dest.len() < self.blocksize;
        decode_block(bytes, 0, format, is_leftover, dest, &mut tmp[..dest.len()])
            .map_err(|e| BloscError(format!("Blosc block {j}: {e}")))
    }
}

#[derive(Clone, Copy, Debug)]
enum Codec {
    BloscLz,
    Lz4,
    Zlib,
}

impl Codec {
    fn from_flags(flags: u8) -> Result<Codec, BloscError> {
        match flags >> 5 {
            0 => Ok(Codec::BloscLz),
            1 => Ok(Codec::Lz4),
            3 => Ok(Codec::Zlib),
            2 => err("Blosc codec snappy is not supported"),
            4 => err("Blosc codec zstd is not supported"),
            c => err(format!("unknown Blosc codec {c}")),
        }
    }
}

/// How a frame's blocks are coded: the header's flags (shuffles, split),
/// the element size the shuffles work on, and the codec.
struct BlockFormat {
    flags: u8,
    typesize: usize,
    codec: Codec,
}

fn decode_block(
    src: &[u8],
    mut offset: usize,
    format: &BlockFormat,
    is_leftover: bool,
    dest: &mut [u8],
    tmp: &mut [u8],
) -> Result<(), BloscError> {
    let (flags, typesize, codec) = (format.flags, format.typesize, format.codec);
    let bsize = dest.len();
    let shuffle = flags & FLAG_SHUFFLE != 0 && typesize > 1;
    let bitshuffle = !shuffle && flags & FLAG_BITSHUFFLE != 0 && bsize >= typesize;
    let dont_split = flags & FLAG_DONT_SPLIT != 0;
    let nsplits = if !dont_split
        && typesize <= MAX_SPLITS
        && bsize / typesize >= MIN_BUFFERSIZE
        && !is_leftover
    {
        typesize
    } else {
        1
    };
    let neblock = bsize / nsplits;
    if neblock * nsplits != bsize {
        return err(format!(
            "block of {bsize} bytes does not split into {nsplits} parts"
        ));
    }
    let target: &mut [u8] = if shuffle || bitshuffle { tmp } else { dest };
    for s in 0..nsplits {
        let csize = match read_u32(src, offset) {
            Some(v) => v as usize,
            None => return err(format!("split offset {offset} outside the frame")),
        };
        offset += 4;
        if csize > src.len() - offset {
            return err(format!("split of {csize} bytes runs past the frame"));
        }
        let input = &src[offset..offset + csize];
        let part = &mut target[s * neblock..(s + 1) * neblock];
        if csize == neblock {
            part.copy_from_slice(input);
        } else {
            let n = match codec {
                Codec::BloscLz => blosclz_decompress(input, part)?,
                Codec::Lz4 => lz4_flex::block::decompress_into(input, part)
                    .map_err(|e| BloscError(format!("LZ4 data is corrupt: {e}")))?,
                Codec::Zlib => zlib_decompress(input, part)?,
            };
            if n != neblock {
                return err(format!(
                    "split decompressed to {n} bytes, expected {neblock}"
                ));
            }
        }
        offset += csize;
    }
    if shuffle {
        unshuffle(typesize, tmp, dest);
    } else if bitshuffle {
        bitunshuffle(typesize, tmp, dest);
    }
    Ok(())
}

/// Inverse of Blosc's byte shuffle: byte `j` of element `i` was stored at
/// `j * n + i`; trailing bytes that do not form a whole element are stored
/// unshuffled.
fn unshuffle(typesize: usize, src: &[u8], dest: &mut [u8]) {
    let n = src.len() / typesize;
    for i in 0..n {
        for j in 0..typesize {
            dest[i * typesize + j] = src[j * n + i];
        }
    }
    let tail = n * typesize;
    dest[tail..].copy_from_slice(&src[tail..]);
}

/// Inverse of the bitshuffle transposition: bit `b` (little-endian within
/// the element) of element `i` was stored at bit index `b * n + i`. Blosc
/// only bit-shuffles whole groups of 8 elements; anything else is a copy.
fn bitunshuffle(typesize: usize, src: &[u8], dest: &mut [u8]) {
    let n = src.len() / typesize;
    if n & 7 != 0 {
        dest.copy_from_slice(src);
        return;
    }
    let whole = n * typesize;
    dest[..whole].fill(0);
    for b in 0..typesize * 8 {
        let row = &src[b * n / 8..(b + 1) * n / 8];
        let (byte, bit) = (b / 8, b % 8);
        for (i, d) in dest[..whole].chunks_exact_mut(typesize).enumerate() {
            let v = (row[i / 8] >> (i % 8)) & 1;
            d[byte] |= v << bit;
        }
    }
    dest[whole..].copy_from_slice(&src[whole..]);
}

/// Inflates one zlib stream into `out`; returns the number of bytes written.
/// Shared with the reader's Zip chunks, which word their errors themselves.
pub(super) fn inflate(input: &[u8], out: &mut [u8]) -> Result<usize, flate2::DecompressError> {
    let mut z = flate2::Decompress::new(true);
    z.decompress(input, out, flate2::FlushDecompress::Finish)?;
    Ok(z.total_out() as usize)
}

fn zlib_decompress(input: &[u8], out: &mut [u8]) -> Result<usize, BloscError> {
    inflate(input, out).map_err(|e| BloscError(format!("zlib data is corrupt: {e}")))
}

/// BloscLZ, a FastLZ derivative. Control bytes below 32 announce a literal
/// run of `ctrl + 1` bytes; others a back-reference whose length is in the
/// top 3 bits (7 = extended by following bytes) and whose distance is in the
/// low 5 bits plus a following byte (all ones = a 16-bit far distance).
/// Returns the number of bytes written; every read and copy is bounds-checked.
fn blosclz_decompress(input: &[u8], out: &mut [u8]) -> Result<usize, BloscError> {
    const MAX_DISTANCE: usize = 8191;
    let corrupt = |what: &str| BloscError(format!("BloscLZ data is corrupt ({what})"));
    if input.is_empty() {
        return Ok(0);
    }
    let mut ip = 0usize;
    let mut op = 0usize;
    let mut ctrl = (input[ip] & 31) as usize;
    ip += 1;
    loop {
        if ctrl >= 32 {
            let mut len = (ctrl >> 5) - 1;
            let mut ofs = (ctrl & 31) << 8;
            if len == 6 {
                loop {
                    let code = *input.get(ip).ok_or_else(|| corrupt("truncated length"))?;
                    ip += 1;
                    len += code as usize;
                    if code != 255 {
                        break;
                    }
                }
            }
            let code = *input.get(ip).ok_or_else(|| corrupt("truncated distance"))? as usize;
            ip += 1;
            len += 3;
            let mut dist = ofs + code;
            if code == 255 && ofs == 31 << 8 {
                let hi = *input
                    .get(ip)
                    .ok_or_else(|| corrupt("truncated far distance"))?;
                let lo = *input
                    .get(ip + 1)
                    .ok_or_else(|| corrupt("truncated far distance"))?;
                ip += 2;
                ofs = ((hi as usize) << 8) | lo as usize;
                dist = ofs + MAX_DISTANCE;
            }
            // The reference starts `dist + 1` bytes back.
            let back = dist + 1;
            if back > op {
                return Err(corrupt("reference before start of output"));
            }
            if len > out.len() - op {
                return Err(corrupt("match runs past end of output"));
            }
            let from = op - back;
            // Byte by byte so overlapping matches repeat, as LZ77 intends.
            for k in 0..len {
                out[op + k] = out[from + k];
            }
            op += len;
        } else {
            let run = ctrl + 1;
            if run > out.len() - op {
                return Err(corrupt("literal run past end of output"));
            }
            if run > input.len() - ip {
                return Err(corrupt("literal run past end of input"));
            }
            out[op..op + run].copy_from_slice(&input[ip..ip + run]);
            op += run;
            ip += run;
        }
        if ip >= input.len() {
            break;
        }
        ctrl = input[ip] as usize;
        ip += 1;
    }
    Ok(op)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(
        flags: u8,
        typesize: u8,
        payload_blocks: &[Vec<u8>],
        nbytes: usize,
        blocksize: usize,
    ) -> Vec<u8> {
        let mut f = vec![2u8, 1, flags, typesize];
        f.extend_from_slice(&(nbytes as u32).to_le_bytes());
        f.extend_from_slice(&(blocksize as u32).to_le_bytes());
        f.extend_from_slice(&0u32.to_le_bytes());
        let starts_at = f.len();
        f.resize(f.len() + 4 * payload_blocks.len(), 0);
        for (j, b) in payload_blocks.iter().enumerate() {
            let start = f.len() as u32;
            f[starts_at + 4 * j..starts_at + 4 * j + 4].copy_from_slice(&start.to_le_bytes());
            f.extend_from_slice(b);
        }
        let c = f.len() as u32;
        f[12..16].copy_from_slice(&c.to_le_bytes());
        f
    }

    #[test]
    fn shuffle_roundtrip_with_stored_splits() {
        // 512 floats, shuffled, each of the 4 splits stored verbatim.
        let data: Vec<u8> = (0..2048u32).map(|i| (i * 7 % 251) as u8).collect();
        let n = 512;
        let mut shuffled = vec![0u8; 2048];
        for i in 0..n {
            for j in 0..4 {
                shuffled[j * n + i] = data[i * 4 + j];
            }
        }
        let mut block = Vec::new();
        for s in 0..4 {
            block.extend_from_slice(&(512u32).to_le_bytes());
            block.extend_from_slice(&shuffled[s * 512..(s + 1) * 512]);
        }
        let f = frame(FLAG_SHUFFLE | (1 << 5), 4, &[block], 2048, 2048);
        assert_eq!(decompress(&f, 2048).unwrap(), data);
        assert!(decompress(&f, 2044).is_err());
        assert!(decompress(&f[..f.len() - 1], 2048).is_err());
    }

    #[test]
    fn bitshuffle_inverts_transpose() {
        let data: Vec<u8> = (0..64u32).map(|i| (i * 37 + 11) as u8).collect();
        let (typesize, n) = (4usize, 16usize);
        let mut shuffled = vec![0u8; 64];
        for i in 0..n {
            for b in 0..typesize * 8 {
                let v = (data[i * typesize + b / 8] >> (b % 8)) & 1;
                let k = b * n + i;
                shuffled[k / 8] |= v << (k % 8);
            }
        }
        let mut out = vec![0u8; 64];
        bitunshuffle(typesize, &shuffled, &mut out);
        assert_eq!(out, data);
    }

    #[test]
    fn blosclz_literals_and_runs() {
        // literal "ab" then a match of length 6 at distance 2 ("ababab").
        let input = [1u8, b'a', b'b', 4 << 5, 1];
        let mut out = [0u8; 8];
        let n = blosclz_decompress(&input, &mut out).unwrap();
        assert_eq!(&out[..n], b"abababab" as &[u8]);
        // A reference before the start is rejected, not read.
        let bad = [0u8, b'a', (1 << 5), 9];
        assert!(blosclz_decompress(&bad, &mut out).is_err());
    }
}

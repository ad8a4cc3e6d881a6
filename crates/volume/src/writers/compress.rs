//! Encoders for the byte streams both formats compress with: zlib
//! (RFC 1950, what OpenVDB's Zip chunks and NanoVDB's ZIP codec hold) and
//! Blosc1 frames (c-blosc's format 2, what OpenVDB's Blosc chunks and
//! NanoVDB's BLOSC codec hold).
//!
//! A Blosc1 frame is a 16-byte header (format version 2, codec format
//! version, flags, type size, uncompressed size, block size, frame size),
//! then one `i32` start offset per block, then the blocks. Frames here are
//! LZ4 blocks of byte-shuffled data, each block one stream (the "don't
//! split" flag) prefixed with its compressed size. When LZ4 does not shrink
//! a block, the whole frame is written as a plain copy instead ("memcpyed"
//! flag, header then the bytes), which every Blosc1 reader accepts.

use crate::loaders::vdb::blosc::{FLAG_DONT_SPLIT, FLAG_MEMCPYED, FLAG_SHUFFLE, HEADER_LEN};
use std::io::Write;

/// c-blosc's frame format and LZ4's codec format versions.
const FORMAT_VERSION: u8 = 2;
const LZ4_FORMAT_VERSION: u8 = 1;
/// The codec number sits in the top three flag bits; LZ4 is 1.
const FLAG_LZ4: u8 = 1 << 5;
/// c-blosc's block sizes for LZ4 at high levels are of this order; small
/// blocks keep the reader's scratch buffers small.
const BLOCK: usize = 256 << 10;
/// The largest payload a Blosc1 frame can describe (its sizes are `i32`).
pub(crate) const BLOSC_MAX: usize = i32::MAX as usize - HEADER_LEN;

/// `bytes` as one zlib stream at the default level.
pub(crate) fn zlib(bytes: &[u8]) -> Vec<u8> {
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    // Writing into a Vec cannot fail.
    let _ = z.write_all(bytes);
    z.finish().unwrap_or_default()
}

/// `bytes` (elements of `typesize` bytes) as one Blosc1 frame; `None` when
/// the payload is too large for a frame.
pub(crate) fn blosc(bytes: &[u8], typesize: usize) -> Option<Vec<u8>> {
    if bytes.len() > BLOSC_MAX || typesize == 0 || typesize > 255 {
        return None;
    }
    Some(lz4_frame(bytes, typesize).unwrap_or_else(|| memcpyed_frame(bytes, typesize)))
}

fn header(flags: u8, typesize: usize, nbytes: usize, blocksize: usize, cbytes: usize) -> Vec<u8> {
    let mut h = Vec::with_capacity(cbytes);
    h.extend_from_slice(&[FORMAT_VERSION, LZ4_FORMAT_VERSION, flags, typesize as u8]);
    for v in [nbytes, blocksize, cbytes] {
        h.extend_from_slice(&(v as u32).to_le_bytes());
    }
    h
}

/// The frame that stores `bytes` as they are.
fn memcpyed_frame(bytes: &[u8], typesize: usize) -> Vec<u8> {
    let n = bytes.len();
    let mut f = header(FLAG_MEMCPYED, typesize, n, n.max(1), n + HEADER_LEN);
    f.extend_from_slice(bytes);
    f
}

/// LZ4 blocks of shuffled data, or `None` when one block does not shrink
/// (c-blosc would then store the frame as a copy too).
fn lz4_frame(bytes: &[u8], typesize: usize) -> Option<Vec<u8>> {
    let n = bytes.len();
    if n == 0 {
        return None;
    }
    // Whole elements per block, so that shuffling never straddles blocks.
    let blocksize = (BLOCK / typesize * typesize).min(n).max(1);
    let nblocks = n.div_ceil(blocksize);
    let mut body = Vec::new();
    let mut starts = Vec::with_capacity(nblocks);
    let mut shuffled = vec![0u8; blocksize];
    let first = HEADER_LEN + 4 * nblocks;
    for block in bytes.chunks(blocksize) {
        let tmp = &mut shuffled[..block.len()];
        shuffle(typesize, block, tmp);
        let packed = lz4_flex::block::compress(tmp);
        if packed.len() >= block.len() {
            return None;
        }
        starts.push(first + body.len());
        body.extend_from_slice(&(packed.len() as u32).to_le_bytes());
        body.extend_from_slice(&packed);
    }
    let cbytes = first + body.len();
    if cbytes >= n + HEADER_LEN || cbytes > i32::MAX as usize {
        return None;
    }
    let flags = FLAG_SHUFFLE | FLAG_DONT_SPLIT | FLAG_LZ4;
    let mut f = header(flags, typesize, n, blocksize, cbytes);
    for s in starts {
        f.extend_from_slice(&(s as u32).to_le_bytes());
    }
    f.extend_from_slice(&body);
    Some(f)
}

/// Blosc's byte shuffle: byte `j` of element `i` goes to `j * n + i`;
/// trailing bytes that do not form a whole element stay where they are.
fn shuffle(typesize: usize, src: &[u8], dest: &mut [u8]) {
    let n = src.len() / typesize;
    for i in 0..n {
        for j in 0..typesize {
            dest[j * n + i] = src[i * typesize + j];
        }
    }
    let tail = n * typesize;
    dest[tail..].copy_from_slice(&src[tail..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loaders::vdb::blosc::decompress;

    #[test]
    fn frames_decode_with_the_reader() {
        let smooth: Vec<u8> = (0..5000u32)
            .flat_map(|i| ((i / 7) as f32).to_le_bytes())
            .collect();
        let mut rng = fogbank_math::Pcg32::new(3, 5);
        let noise: Vec<u8> = (0..3001).map(|_| rng.next_u32() as u8).collect();
        let big: Vec<u8> = (0..600_000u32).map(|i| (i / 1000) as u8).collect();
        for (bytes, ts) in [(&smooth, 4), (&noise, 4), (&big, 1), (&Vec::new(), 4)] {
            let f = blosc(bytes, ts).unwrap();
            assert_eq!(&decompress(&f, bytes.len()).unwrap(), bytes);
        }
        assert!(blosc(&smooth, 4).unwrap().len() < smooth.len() / 2);
        assert_eq!(blosc(&noise, 4).unwrap()[2], FLAG_MEMCPYED);
    }

    #[test]
    fn zlib_round_trip() {
        let bytes: Vec<u8> = (0..10_000u32).map(|i| (i % 17) as u8).collect();
        let z = zlib(&bytes);
        let mut out = Vec::new();
        use std::io::Read;
        flate2::read::ZlibDecoder::new(&z[..])
            .read_to_end(&mut out)
            .unwrap();
        assert_eq!(out, bytes);
    }
}

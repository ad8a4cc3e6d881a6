//! A grid's stored bytes → its grid buffer, read front to back
//! (`io::Internal::read`): raw; ZIP, a `u64` compressed size and one zlib
//! stream of the whole buffer; BLOSC, the buffer cut into chunks of at most
//! 2³⁰ bytes, each stored as a `u64` compressed size and one Blosc1 frame.
//!
//! The buffer is never held whole: the tree reader takes the internal nodes
//! in front of the first leaf, then the leaves run by run, so loading a grid
//! costs the grid fogbank builds from it plus one run of leaves (and, for
//! BLOSC, one block of a frame).

use std::io::Read;
use std::path::Path;

use super::segment::{Codec, GridEntry, Source};
use crate::error::{Result, VolumeError};
use crate::loaders::vdb::blosc::FrameStream;

/// NanoVDB cuts Blosc input into chunks of this size.
const BLOSC_CHUNK: u64 = 1 << 30;
/// No codec that Blosc or zlib use expands data more than this (zlib's
/// limit is about 1032:1), so a frame or stream claiming more is corrupt
/// and is rejected before its output is allocated.
const MAX_RATIO: u64 = 1100;

/// The decoded grid buffer of one grid, as a sequential reader that knows
/// how far it has read.
pub(super) struct GridStream<'a> {
    inner: Box<dyn Read + 'a>,
    codec: Codec,
    /// Bytes of the buffer read so far, and the size the metadata declares.
    pos: usize,
    size: usize,
    path: &'a Path,
    name: &'a str,
    data_pos: u64,
}

impl<'a> GridStream<'a> {
    /// The buffer of `e`, whose stored bytes `src` holds at `e.data_pos`.
    pub(super) fn open(path: &'a Path, src: &'a mut Source, e: &'a GridEntry) -> Result<Self> {
        let fail = |msg: String| stream_error(path, e, msg);
        let size = usize::try_from(e.grid_size)
            .map_err(|_| fail(format!("a {}-byte grid buffer is too large", e.grid_size)))?;
        let stored = usize::try_from(e.file_size)
            .map_err(|_| fail(format!("{} stored bytes are too many", e.file_size)))?;
        let mut raw = src.reader(path, e.data_pos, stored)?;
        let inner: Box<dyn Read + 'a> = match e.codec {
            Codec::None => {
                if e.grid_size != e.file_size {
                    return Err(fail(format!(
                        "uncompressed grid of {} stored bytes declares a {}-byte buffer",
                        e.file_size, e.grid_size
                    )));
                }
                raw
            }
            Codec::Zip => {
                let csize = block_size(&mut raw, e.file_size, "ZIP stream").map_err(fail)?;
                if let Some(m) = too_large(e.grid_size, csize) {
                    return Err(fail(m));
                }
                Box::new(flate2::read::ZlibDecoder::new(raw.take(csize)))
            }
            Codec::Blosc => Box::new(BloscChunks {
                raw,
                residual: e.grid_size,
                stored_left: e.file_size,
                frame: None,
                chunk_stored: 0,
                frame_pos: 0,
                block: 0,
                stored_block: Vec::new(),
                out: Vec::new(),
                out_pos: 0,
                tmp: Vec::new(),
            }),
        };
        Ok(GridStream {
            inner,
            codec: e.codec,
            pos: 0,
            size,
            path,
            name: &e.name,
            data_pos: e.data_pos,
        })
    }

    /// The declared size of the buffer.
    pub(super) fn size(&self) -> usize {
        self.size
    }

    /// How many bytes have been read.
    pub(super) fn pos(&self) -> usize {
        self.pos
    }

    fn fail(&self, msg: String) -> VolumeError {
        VolumeError::format(
            self.path,
            format!(
                "{msg} in grid `{}` at offset {} (byte {} of the grid buffer)",
                self.name, self.data_pos, self.pos
            ),
        )
    }

    fn read_error(&self, e: std::io::Error) -> VolumeError {
        match self.codec {
            Codec::None => VolumeError::io(self.path, e),
            Codec::Zip => self.fail(format!("corrupt ZIP stream: {e}")),
            Codec::Blosc => self.fail(e.to_string()),
        }
    }

    /// Appends the next `n` bytes of the buffer to `buf` (which grows as
    /// they arrive, so a stream that ends early never costs its claim).
    pub(super) fn read_into(&mut self, buf: &mut Vec<u8>, n: usize) -> Result<()> {
        if n > self.size - self.pos {
            return Err(self.fail(format!(
                "a read of {n} bytes runs past the end of the {}-byte grid buffer",
                self.size
            )));
        }
        let got = (&mut self.inner)
            .take(n as u64)
            .read_to_end(buf)
            .map_err(|e| self.read_error(e))?;
        self.pos += got;
        if got < n {
            return Err(self.fail(format!(
                "the {} data ends after {} of the {} bytes the metadata declares",
                self.codec.name(),
                self.pos,
                self.size
            )));
        }
        Ok(())
    }

    /// Reads on to byte `at` of the buffer, discarding what lies before.
    pub(super) fn skip_to(&mut self, at: usize) -> Result<()> {
        let n = at.checked_sub(self.pos).ok_or_else(|| {
            self.fail(format!(
                "byte {at} lies behind bytes already read (nodes overlap)"
            ))
        })?;
        let mut sink = Vec::new();
        let mut left = n;
        while left > 0 {
            let step = left.min(1 << 16);
            sink.clear();
            self.read_into(&mut sink, step)?;
            left -= step;
        }
        Ok(())
    }

    /// Reads the rest of the buffer and checks that the stored data ends
    /// with it: a ZIP stream that inflates past the declared size, or bytes
    /// after the last BLOSC chunk, are errors.
    pub(super) fn finish(mut self) -> Result<()> {
        self.skip_to(self.size)?;
        let mut one = [0u8; 1];
        let extra = self.inner.read(&mut one).map_err(|e| self.read_error(e))?;
        if extra > 0 {
            return Err(self.fail(format!(
                "the {} data holds more than the {} bytes the metadata declares",
                self.codec.name(),
                self.size
            )));
        }
        Ok(())
    }
}

fn stream_error(path: &Path, e: &GridEntry, msg: String) -> VolumeError {
    VolumeError::format(
        path,
        format!("{msg} in grid `{}` at offset {}", e.name, e.data_pos),
    )
}

/// A `u64` size prefix, checked against the `left` stored bytes it and its
/// block must fit in.
fn block_size(raw: &mut dyn Read, left: u64, what: &str) -> std::result::Result<u64, String> {
    let mut b = [0u8; 8];
    if left < 8 || raw.read_exact(&mut b).is_err() {
        return Err(format!("truncated {what} size"));
    }
    let size = u64::from_le_bytes(b);
    if size > left - 8 {
        return Err(format!(
            "{what} claims {size} bytes but {} remain",
            left - 8
        ));
    }
    Ok(size)
}

fn too_large(size: u64, stored: u64) -> Option<String> {
    (size > stored.saturating_mul(MAX_RATIO).saturating_add(4096)).then(|| {
        format!("{stored} compressed bytes cannot hold the declared {size}-byte grid buffer")
    })
}

/// The BLOSC chunks of a grid as one reader. A chunk's frame is read front
/// to back, one block's stored bytes at a time, each decoded as it comes.
struct BloscChunks<'a> {
    raw: Box<dyn Read + 'a>,
    /// Decoded bytes not yet in a chunk, and stored bytes not yet read.
    residual: u64,
    stored_left: u64,
    /// The current chunk's frame, its stored size and how much of it is read.
    frame: Option<FrameStream>,
    chunk_stored: usize,
    frame_pos: usize,
    /// The next block of the current frame to decode.
    block: usize,
    stored_block: Vec<u8>,
    out: Vec<u8>,
    out_pos: usize,
    tmp: Vec<u8>,
}

fn invalid(msg: String) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidData, msg)
}

fn corrupt(e: impl std::fmt::Display) -> std::io::Error {
    invalid(format!("corrupt BLOSC chunk: {e}"))
}

impl BloscChunks<'_> {
    /// The next `n` stored bytes of the current chunk into `buf`.
    fn read_stored(&mut self, n: usize, buf: &mut Vec<u8>) -> std::io::Result<()> {
        buf.clear();
        (&mut self.raw).take(n as u64).read_to_end(buf)?;
        if buf.len() < n {
            return Err(invalid("truncated BLOSC chunk".into()));
        }
        self.frame_pos += n;
        Ok(())
    }

    /// Starts the next chunk; `false` when every chunk is read.
    fn next_chunk(&mut self) -> std::io::Result<bool> {
        if self.residual == 0 {
            if self.stored_left > 0 {
                return Err(invalid(format!(
                    "{} bytes after the last BLOSC chunk",
                    self.stored_left
                )));
            }
            return Ok(false);
        }
        let size = block_size(&mut self.raw, self.stored_left, "BLOSC chunk").map_err(invalid)?;
        self.stored_left -= 8 + size;
        let chunk = self.residual.min(BLOSC_CHUNK);
        if let Some(m) = too_large(chunk, size) {
            return Err(invalid(m));
        }
        (self.chunk_stored, self.frame_pos) = (size as usize, 0);
        let mut head = Vec::new();
        self.read_stored(16.min(self.chunk_stored), &mut head)?;
        let mut frame = FrameStream::parse(&head, self.chunk_stored, chunk as usize)
            .map_err(corrupt)?
            .ok_or_else(|| corrupt("empty frame"))?;
        self.read_stored(frame.offsets_len(), &mut head)?;
        frame.set_offsets(&head, true).map_err(corrupt)?;
        self.frame = Some(frame);
        self.residual -= chunk;
        self.block = 0;
        Ok(true)
    }

    /// Decodes the next block into `out`; `false` at the end of the data.
    fn next_block(&mut self) -> std::io::Result<bool> {
        loop {
            if let Some(frame) = self.frame.take() {
                if self.block < frame.blocks() {
                    let bytes = frame.block_bytes(self.block);
                    let mut stored = std::mem::take(&mut self.stored_block);
                    // Offsets increase (`set_offsets`): never behind.
                    let gap = bytes.start.saturating_sub(self.frame_pos);
                    self.read_stored(gap, &mut stored)?;
                    self.read_stored(bytes.len(), &mut stored)?;
                    self.out.resize(frame.block_len(self.block), 0);
                    self.tmp.resize(frame.block_size(), 0);
                    frame
                        .decode_block(self.block, &stored, &mut self.out, &mut self.tmp)
                        .map_err(corrupt)?;
                    self.stored_block = stored;
                    self.block += 1;
                    self.out_pos = 0;
                    self.frame = Some(frame);
                    return Ok(true);
                }
                // What the chunk holds after its frame is unused.
                let rest = self.chunk_stored.saturating_sub(self.frame_pos);
                std::io::copy(&mut (&mut self.raw).take(rest as u64), &mut std::io::sink())?;
            }
            if !self.next_chunk()? {
                return Ok(false);
            }
        }
    }
}

impl Read for BloscChunks<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.out_pos == self.out.len() && !self.next_block()? {
            return Ok(0);
        }
        let n = buf.len().min(self.out.len() - self.out_pos);
        buf[..n].copy_from_slice(&self.out[self.out_pos..self.out_pos + n]);
        self.out_pos += n;
        Ok(n)
    }
}

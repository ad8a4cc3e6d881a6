//! The bounds-checked view of one decoded grid buffer that every part of
//! the tree reader goes through. Offsets are byte offsets into the grid
//! buffer, as NanoVDB's own node offsets are; errors name them, and the
//! file offset too when the buffer is stored uncompressed.

use std::path::Path;

use crate::error::{Result, VolumeError};

pub(super) struct GridBuf<'a> {
    pub(super) data: &'a [u8],
    pub(super) path: &'a Path,
    pub(super) grid: &'a str,
    /// File offset of byte 0 when the buffer is stored as is.
    pub(super) file_pos: Option<u64>,
}

impl<'a> GridBuf<'a> {
    pub(super) fn len(&self) -> usize {
        self.data.len()
    }

    pub(super) fn fail(&self, at: usize, msg: impl std::fmt::Display) -> VolumeError {
        let place = match self.file_pos {
            Some(p) => format!("offset {} (byte {at} of the grid buffer)", p + at as u64),
            None => format!("byte {at} of the decompressed grid buffer"),
        };
        VolumeError::format(
            self.path,
            format!("{msg} in grid `{}` at {place}", self.grid),
        )
    }

    /// `n` bytes at `at`.
    pub(super) fn bytes(&self, at: usize, n: usize, what: &str) -> Result<&'a [u8]> {
        match at.checked_add(n) {
            Some(end) if end <= self.data.len() => Ok(&self.data[at..end]),
            _ => Err(self.fail(
                at,
                format!(
                    "{what} ({n} bytes) runs past the end of the {}-byte grid buffer",
                    self.data.len()
                ),
            )),
        }
    }

    pub(super) fn array<const N: usize>(&self, at: usize, what: &str) -> Result<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.bytes(at, N, what)?);
        Ok(a)
    }

    pub(super) fn u8(&self, at: usize, what: &str) -> Result<u8> {
        Ok(self.array::<1>(at, what)?[0])
    }
    pub(super) fn u32(&self, at: usize, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(at, what)?))
    }
    pub(super) fn u64(&self, at: usize, what: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(self.array(at, what)?))
    }
    pub(super) fn i64(&self, at: usize, what: &str) -> Result<i64> {
        Ok(i64::from_le_bytes(self.array(at, what)?))
    }
    pub(super) fn f32(&self, at: usize, what: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.array(at, what)?))
    }
    pub(super) fn f64(&self, at: usize, what: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.array(at, what)?))
    }

    /// A bit mask of `words` 64-bit words at `at`.
    pub(super) fn mask(&self, at: usize, words: usize, what: &str) -> Result<Vec<u64>> {
        let s = self.bytes(at, words * 8, what)?;
        Ok(s.chunks_exact(8)
            .map(|c| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect())
    }

    /// The node a parent at `from` reaches through the signed byte offset
    /// `offset`, which must lie in the buffer with `size` bytes after it.
    pub(super) fn child(&self, from: usize, offset: i64, size: usize, what: &str) -> Result<usize> {
        let at = (from as i64)
            .checked_add(offset)
            .and_then(|a| usize::try_from(a).ok())
            .filter(|&a| a.checked_add(size).is_some_and(|e| e <= self.data.len()));
        at.ok_or_else(|| {
            self.fail(
                from,
                format!(
                    "{what} offset {offset} points outside the {}-byte grid buffer",
                    self.data.len()
                ),
            )
        })
    }
}

//! The bounds-checked view of a window of one decoded grid buffer that
//! every part of the tree reader goes through: the internal nodes before
//! the first leaf, or a run of leaves, as the buffer streams past (the
//! whole buffer is never held). Offsets are byte offsets into the grid
//! buffer, as NanoVDB's own node offsets are; errors name them, and the
//! file offset too when the buffer is stored uncompressed.

use std::path::Path;

use crate::error::{Result, VolumeError};

pub(super) struct GridBuf<'a> {
    /// The window's bytes: buffer bytes `base..base + data.len()`.
    pub(super) data: &'a [u8],
    pub(super) base: usize,
    /// The whole buffer's size, which offsets to nodes are checked against.
    pub(super) total: usize,
    pub(super) path: &'a Path,
    pub(super) grid: &'a str,
    /// File offset of byte 0 when the buffer is stored as is, else the
    /// codec it was decoded from (a corrupt stream shows as nonsense here).
    pub(super) stored: std::result::Result<u64, &'static str>,
}

impl<'a> GridBuf<'a> {
    /// The whole buffer's size.
    pub(super) fn len(&self) -> usize {
        self.total
    }

    /// The same buffer's window `data` starting at buffer byte `base`.
    pub(super) fn window<'b>(&self, data: &'b [u8], base: usize) -> GridBuf<'b>
    where
        'a: 'b,
    {
        GridBuf {
            data,
            base,
            total: self.total,
            path: self.path,
            grid: self.grid,
            stored: self.stored,
        }
    }

    pub(super) fn fail(&self, at: usize, msg: impl std::fmt::Display) -> VolumeError {
        let place = match self.stored {
            Ok(p) => format!("offset {} (byte {at} of the grid buffer)", p + at as u64),
            Err(codec) => {
                format!("byte {at} of the grid buffer decompressed from its {codec} data")
            }
        };
        VolumeError::format(
            self.path,
            format!("{msg} in grid `{}` at {place}", self.grid),
        )
    }

    /// `n` bytes at `at`.
    pub(super) fn bytes(&self, at: usize, n: usize, what: &str) -> Result<&'a [u8]> {
        let end = match at.checked_add(n) {
            Some(end) if end <= self.total => end,
            _ => {
                return Err(self.fail(
                    at,
                    format!(
                        "{what} ({n} bytes) runs past the end of the {}-byte grid buffer",
                        self.total
                    ),
                ))
            }
        };
        let window_end = self.base + self.data.len();
        if at < self.base || end > window_end {
            return Err(self.fail(
                at,
                format!(
                    "{what} ({n} bytes) lies outside bytes {}..{window_end}, where NanoVDB puts it",
                    self.base
                ),
            ));
        }
        Ok(&self.data[at - self.base..end - self.base])
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
            .filter(|&a| a.checked_add(size).is_some_and(|e| e <= self.total));
        at.ok_or_else(|| {
            self.fail(
                from,
                format!(
                    "{what} offset {offset} points outside the {}-byte grid buffer",
                    self.total
                ),
            )
        })
    }
}

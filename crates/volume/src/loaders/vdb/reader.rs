//! The bounds-checked byte cursor every part of the reader goes through.

use std::path::Path;

use crate::error::{Result, VolumeError};

/// A bounds-checked little-endian cursor whose errors carry file, context
/// (which grid or header part) and offset.
pub(super) struct Reader<'a> {
    pub(super) path: &'a Path,
    /// The file, or a window of it starting at file offset `base`.
    pub(super) data: &'a [u8],
    pub(super) base: usize,
    pos: usize,
    pub(super) context: String,
}

pub(super) fn grid_context(name: &str) -> String {
    format!("in grid `{name}`")
}

impl<'a> Reader<'a> {
    pub(super) fn new(path: &'a Path, data: &'a [u8], context: String) -> Self {
        Reader {
            path,
            data,
            base: 0,
            pos: 0,
            context,
        }
    }

    pub(super) fn window(path: &'a Path, data: &'a [u8], base: usize, context: String) -> Self {
        Reader {
            path,
            data,
            base,
            pos: 0,
            context,
        }
    }

    /// Position in the file, for messages and seeks.
    pub(super) fn offset(&self) -> usize {
        self.base + self.pos
    }

    pub(super) fn fail_at(&self, pos: usize, msg: impl std::fmt::Display) -> VolumeError {
        VolumeError::format(self.path, format!("{msg} {} at offset {pos}", self.context))
    }

    pub(super) fn fail(&self, msg: impl std::fmt::Display) -> VolumeError {
        self.fail_at(self.offset(), msg)
    }

    pub(super) fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    pub(super) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        if n > self.remaining() {
            return Err(self.fail(format!(
                "truncated {what} (needs {n} bytes, {} left)",
                self.remaining()
            )));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    pub(super) fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let s = self.take(N, what)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }

    pub(super) fn u8(&mut self, what: &str) -> Result<u8> {
        Ok(self.array::<1>(what)?[0])
    }
    pub(super) fn u32(&mut self, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }
    pub(super) fn i32(&mut self, what: &str) -> Result<i32> {
        Ok(i32::from_le_bytes(self.array(what)?))
    }
    pub(super) fn i64(&mut self, what: &str) -> Result<i64> {
        Ok(i64::from_le_bytes(self.array(what)?))
    }
    pub(super) fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.array(what)?))
    }
    pub(super) fn f64(&mut self, what: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }
    pub(super) fn vec3d(&mut self, what: &str) -> Result<[f64; 3]> {
        Ok([self.f64(what)?, self.f64(what)?, self.f64(what)?])
    }
    pub(super) fn coord(&mut self, what: &str) -> Result<[i32; 3]> {
        Ok([self.i32(what)?, self.i32(what)?, self.i32(what)?])
    }

    /// A `u32`-length-prefixed string. Names are ASCII in practice; anything
    /// else is kept lossily so that it can still be shown in messages.
    pub(super) fn string(&mut self, what: &str) -> Result<String> {
        let start = self.offset();
        let len = self.u32(what)? as usize;
        if len > self.remaining() {
            return Err(self.fail_at(
                start,
                format!(
                    "{what} claims {len} bytes but only {} remain",
                    self.remaining()
                ),
            ));
        }
        let s = self.take(len, what)?;
        Ok(String::from_utf8_lossy(s).into_owned())
    }

    pub(super) fn mask(&mut self, words: usize, what: &str) -> Result<Vec<u64>> {
        let s = self.take(words * 8, what)?;
        Ok(s.chunks_exact(8)
            .map(|c| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect())
    }

    pub(super) fn seek(&mut self, pos: usize, what: &str) -> Result<()> {
        match pos.checked_sub(self.base) {
            Some(rel) if rel <= self.data.len() => {
                self.pos = rel;
                Ok(())
            }
            _ => Err(self.fail(format!(
                "{what} offset {pos} lies outside the bytes read ({}..{})",
                self.base,
                self.base + self.data.len()
            ))),
        }
    }
}

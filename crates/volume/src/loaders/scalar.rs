//! Scalar volumes of scientific files (NIfTI, NRRD): the values in the
//! file's own units (after NIfTI's `scl_slope`/`scl_inter`), x fastest,
//! with the file's voxel-to-world map. fogbank keeps a voxel's value at its
//! cell centre, so `index_to_world` already includes the −½ shift from the
//! formats' node-centred convention (their affine maps voxel *centres* at
//! integer indices).

use super::sample::SampleType;
use crate::grid::{check_dims, BrickGrid};
use crate::{Result, VolumeError};
use fogbank_math::{DAffine3, DVec3};
use std::path::Path;

/// Largest decoded volume a loader accepts (2^31 voxels, 8 GiB as f32).
pub const MAX_VOXELS: u64 = 1 << 31;

#[derive(Clone, Debug)]
pub struct ScalarVolume {
    pub dims: [u32; 3],
    /// Values in file units, `dims[0]` fastest.
    pub values: Vec<f32>,
    /// fogbank index space (cell `i` spans `[i, i + 1]`) → world (RAS mm
    /// for both formats).
    pub index_to_world: DAffine3,
    /// What the file said, for `fogbank info`: format, sample type,
    /// which placement the affine came from.
    pub description: String,
    pub sample_type: SampleType,
}

impl ScalarVolume {
    /// The map of a format whose affine `a` takes integer voxel indices to
    /// voxel centres: fogbank index `p` ↦ `a(p − ½)`.
    pub fn node_centred(a: DAffine3) -> DAffine3 {
        a * DAffine3::from_translation(DVec3::splat(-0.5))
    }

    /// (min, max) of the finite values; `None` when there are none.
    pub fn range(&self) -> Option<(f32, f32)> {
        let (lo, hi) = self
            .values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        (lo <= hi).then_some((lo, hi))
    }

    /// Counts of the finite values in `bins` equal bins over [`Self::range`].
    pub fn histogram(&self, bins: usize) -> Vec<u64> {
        let mut h = vec![0u64; bins.max(1)];
        let Some((lo, hi)) = self.range() else {
            return h;
        };
        let scale = if hi > lo {
            h.len() as f64 / (hi - lo) as f64
        } else {
            0.0
        };
        for &v in self.values.iter().filter(|v| v.is_finite()) {
            let b = (((v - lo) as f64 * scale) as usize).min(h.len() - 1);
            h[b] += 1;
        }
        h
    }

    /// Density without a transfer function: the value range mapped onto
    /// [0, 1] (ParaView's "rescale to data range"), non-finite values 0.
    pub fn normalised_grid(&self) -> Result<BrickGrid<f32>> {
        let (lo, hi) = self.range().unwrap_or((0.0, 1.0));
        let inv = if hi > lo { 1.0 / (hi - lo) } else { 0.0 };
        let [nx, ny, _] = self.dims.map(|d| d as usize);
        BrickGrid::from_fn(self.dims, |i, j, k| {
            let v = self.values[(k as usize * ny + j as usize) * nx + i as usize];
            if v.is_finite() {
                ((v - lo) * inv).clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
    }
}

/// Checks 3D `dims` (any further axes already reduced) and returns the
/// voxel count, before anything is allocated.
pub fn check_volume(path: &Path, dims: [u64; 3]) -> Result<usize> {
    check_dims(dims).map_err(|e| VolumeError::format(path, e.to_string()))?;
    let n: u64 = dims.iter().product();
    if n > MAX_VOXELS {
        return Err(VolumeError::format(
            path,
            format!("{n} voxels, more than the limit of {MAX_VOXELS}"),
        ));
    }
    Ok(n as usize)
}

/// Reads all of `path`, gunzipping it when it starts with the gzip magic,
/// refusing more than `limit` bytes (so a gzip bomb cannot exhaust memory).
pub fn read_maybe_gzip(path: &Path, limit: u64) -> Result<Vec<u8>> {
    let raw = std::fs::read(path).map_err(|e| VolumeError::io(path, e))?;
    decompress_if_gzip(path, raw, limit)
}

/// `bytes` itself, or its gzip decompression (all members) if it starts
/// with 1f 8b; at most `limit` bytes either way.
pub fn decompress_if_gzip(path: &Path, bytes: Vec<u8>, limit: u64) -> Result<Vec<u8>> {
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Ok(bytes);
    }
    gunzip(path, &bytes, limit)
}

/// All gzip members of `bytes`, at most `limit` bytes.
pub fn gunzip(path: &Path, bytes: &[u8], limit: u64) -> Result<Vec<u8>> {
    use std::io::Read;
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| VolumeError::format(path, format!("gzip data: {e}")))?;
    if out.len() as u64 > limit {
        return Err(VolumeError::format(
            path,
            format!("gzip data decompresses to more than the {limit} bytes the header describes"),
        ));
    }
    Ok(out)
}

/// Decodes `count` samples of `ty` starting at byte `offset` of `bytes`,
/// naming the shortfall when the data is too short.
pub fn decode_samples(
    path: &Path,
    bytes: &[u8],
    offset: usize,
    count: usize,
    ty: SampleType,
    big_endian: bool,
) -> Result<Vec<f32>> {
    let need = count
        .checked_mul(ty.bytes())
        .and_then(|n| n.checked_add(offset))
        .ok_or_else(|| VolumeError::format(path, "data size overflows"))?;
    if bytes.len() < need {
        return Err(VolumeError::format(
            path,
            format!(
                "data ends at byte {}, but {count} {} samples from byte {offset} need {need}",
                bytes.len(),
                ty.name()
            ),
        ));
    }
    Ok(bytes[offset..need]
        .chunks_exact(ty.bytes())
        .map(|b| ty.decode(b, big_endian) as f32)
        .collect())
}

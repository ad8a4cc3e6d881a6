//! Mitsuba `.vol` grids (binary, version 3).
//!
//! | bytes | content |
//! |---|---|
//! | 0–3 | `V`, `O`, `L`, 3 |
//! | 4–7 | encoding (i32; 1 = float32, the only one Mitsuba 3 writes) |
//! | 8–19 | xres, yres, zres (i32) |
//! | 20–23 | channels (i32: 1, 3 or 6) |
//! | 24–47 | bbox xmin ymin zmin xmax ymax zmax (f32) |
//! | 48– | f32 data, index `((z·yres + y)·xres + x)·channels + c` |
//!
//! Mitsuba samples the grid with cell centres at `(i + ½)/res` of the bbox,
//! clamped at the border — exactly fogbank's grid convention, so the
//! index→world map is just the bbox scaled by `1/res`.

use crate::grid::BrickGrid;
use crate::{Result, VolumeError};
use fogbank_math::DAffine3;
use std::path::Path;

#[derive(Clone, Debug)]
pub struct VolFile {
    pub dims: [u32; 3],
    pub channels: u32,
    pub bbox_min: [f32; 3],
    pub bbox_max: [f32; 3],
    /// Values in file order (`channels` interleaved).
    pub data: Vec<f32>,
}

fn i32_at(b: &[u8], o: usize) -> i32 {
    i32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]])
}
fn f32_at(b: &[u8], o: usize) -> f32 {
    f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]])
}

/// Parses a `.vol` from memory; `path` only names the file in errors.
pub fn parse_vol(path: &Path, bytes: &[u8]) -> Result<VolFile> {
    let err = |m: String| VolumeError::format(path, m);
    if bytes.len() < 48 {
        return Err(err(format!(
            "file is {} bytes, shorter than the 48-byte .vol header",
            bytes.len()
        )));
    }
    if &bytes[0..3] != b"VOL" || bytes[3] != 3 {
        return Err(err(
            "not a Mitsuba .vol file (expected bytes `VOL` and version 3)".into(),
        ));
    }
    let encoding = i32_at(bytes, 4);
    if encoding != 1 {
        return Err(err(format!(
            "unsupported encoding {encoding} (only 1 = float32 is supported)"
        )));
    }
    let res = [i32_at(bytes, 8), i32_at(bytes, 12), i32_at(bytes, 16)];
    if res.iter().any(|&r| r <= 0) {
        return Err(err(format!(
            "invalid resolution {}×{}×{}",
            res[0], res[1], res[2]
        )));
    }
    let channels = i32_at(bytes, 20);
    if ![1, 3, 6].contains(&channels) {
        return Err(err(format!(
            "invalid channel count {channels} (expected 1, 3 or 6)"
        )));
    }
    let bbox: [f32; 6] = std::array::from_fn(|i| f32_at(bytes, 24 + 4 * i));
    if bbox.iter().any(|v| !v.is_finite()) || (0..3).any(|a| bbox[a + 3] <= bbox[a]) {
        return Err(err(format!("invalid bounding box {bbox:?}")));
    }
    crate::grid::check_dims(res.map(|r| r as u64)).map_err(|e| err(e.to_string()))?;
    let count = res.iter().map(|&r| r as u64).product::<u64>() * channels as u64;
    let expected = 48 + count * 4;
    if (bytes.len() as u64) < expected {
        return Err(err(format!(
            "truncated: {}×{}×{}×{} values need {} bytes, file has {}",
            res[0],
            res[1],
            res[2],
            channels,
            expected,
            bytes.len()
        )));
    }
    let data = bytes[48..expected as usize]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    Ok(VolFile {
        dims: res.map(|r| r as u32),
        channels: channels as u32,
        bbox_min: [bbox[0], bbox[1], bbox[2]],
        bbox_max: [bbox[3], bbox[4], bbox[5]],
        data,
    })
}

pub fn read_vol(path: &Path) -> Result<VolFile> {
    let bytes = std::fs::read(path).map_err(|e| VolumeError::io(path, e))?;
    parse_vol(path, &bytes)
}

impl VolFile {
    /// One channel as a grid (non-finite values become 0).
    pub fn channel_grid(&self, channel: u32) -> Result<BrickGrid<f32>> {
        if channel >= self.channels {
            return Err(VolumeError::Invalid(format!(
                "channel {channel} requested from a {}-channel grid",
                self.channels
            )));
        }
        let [nx, ny, _] = self.dims.map(|d| d as usize);
        let c = self.channels as usize;
        BrickGrid::from_fn(self.dims, |i, j, k| {
            let v = self.data
                [((k as usize * ny + j as usize) * nx + i as usize) * c + channel as usize];
            if v.is_finite() {
                v
            } else {
                0.0
            }
        })
    }

    /// Index `p ∈ [0, res]` ↦ `bbox_min + p / res · (bbox_max − bbox_min)`.
    pub fn index_to_world(&self) -> DAffine3 {
        crate::medium::box_transform(
            self.dims,
            self.bbox_min.map(f64::from),
            self.bbox_max.map(f64::from),
        )
    }
}

/// Writes a `.vol` (used by tests and the peer-renderer scripts).
pub fn write_vol(
    path: &Path,
    dims: [u32; 3],
    channels: u32,
    bbox: [f32; 6],
    data: &[f32],
) -> std::io::Result<()> {
    let mut out = Vec::with_capacity(48 + data.len() * 4);
    out.extend_from_slice(b"VOL\x03");
    out.extend_from_slice(&1i32.to_le_bytes());
    for d in dims {
        out.extend_from_slice(&(d as i32).to_le_bytes());
    }
    out.extend_from_slice(&(channels as i32).to_le_bytes());
    for b in bbox {
        out.extend_from_slice(&b.to_le_bytes());
    }
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, out)
}

#[cfg(test)]
mod vol_test {
    use super::*;
    use fogbank_math::testdata::external_data;

    #[test]
    fn reads_mitsuba_test_grids() {
        let Some(p) = external_data("sigmat.vol") else {
            return;
        };
        let v = read_vol(&p).unwrap();
        assert_eq!((v.dims, v.channels), ([16, 16, 16], 1));
        assert_eq!((v.bbox_min, v.bbox_max), ([0.0; 3], [1.0; 3]));
        let max = v.data.iter().cloned().fold(f32::MIN, f32::max);
        assert!(max <= 5.0 && max > 1.0);
        let Some(p) = external_data("albedo.vol") else {
            return;
        };
        let a = read_vol(&p).unwrap();
        assert_eq!(a.channels, 3);
        assert!(a.data.iter().all(|x| (0.0..=1.0).contains(x)));
    }

    #[test]
    fn malformed_files_are_errors_not_panics() {
        let dir = std::env::temp_dir().join("fogbank_vol_test");
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("ok.vol");
        write_vol(&p, [3, 2, 2], 1, [0., 0., 0., 1., 1., 1.], &[0.5; 12]).unwrap();
        let good = std::fs::read(&p).unwrap();
        assert!(parse_vol(&p, &good).is_ok());
        for cut in 0..good.len() {
            let e = parse_vol(&p, &good[..cut]).unwrap_err().to_string();
            assert!(e.contains("ok.vol"), "{e}");
        }
        let mut huge = good.clone();
        huge[8..12].copy_from_slice(&i32::MAX.to_le_bytes());
        huge[12..16].copy_from_slice(&i32::MAX.to_le_bytes());
        assert!(parse_vol(&p, &huge).is_err());
        huge[8..12].copy_from_slice(&60000i32.to_le_bytes());
        huge[12..16].copy_from_slice(&60000i32.to_le_bytes());
        assert!(parse_vol(&p, &huge)
            .unwrap_err()
            .to_string()
            .contains("truncated"));
        let mut neg = good.clone();
        neg[20..24].copy_from_slice(&(-1i32).to_le_bytes());
        assert!(parse_vol(&p, &neg).is_err());
    }
}

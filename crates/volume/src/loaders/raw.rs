//! Raw scientific volumes: headerless little-endian arrays, x fastest.
//!
//! Dimensions and type come from the scene (`dims`, `type`) or from the Open
//! SciVis naming pattern `name_XxYxZ_type.raw` (`uint8`, `uint16`, `int16`,
//! `float32`, `float64`). Integer types are normalised to [0, 1] by their
//! maximum value, so a `sigma_t_scale` means the same for every file.

use super::sample::SampleType;
use crate::grid::{check_dims, BrickGrid};
use crate::{Result, VolumeError};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RawType {
    U8,
    U16,
    I16,
    F32,
    F64,
}

impl RawType {
    pub fn parse(s: &str) -> Option<RawType> {
        match s {
            "u8" | "uint8" => Some(RawType::U8),
            "u16" | "uint16" => Some(RawType::U16),
            "i16" | "int16" => Some(RawType::I16),
            "f32" | "float32" | "float" => Some(RawType::F32),
            "f64" | "float64" | "double" => Some(RawType::F64),
            _ => None,
        }
    }

    pub fn bytes(self) -> usize {
        self.sample_type().bytes()
    }

    fn sample_type(self) -> SampleType {
        match self {
            RawType::U8 => SampleType::U8,
            RawType::U16 => SampleType::U16,
            RawType::I16 => SampleType::I16,
            RawType::F32 => SampleType::F32,
            RawType::F64 => SampleType::F64,
        }
    }

    /// A little-endian sample, integer types normalised by their maximum.
    fn decode(self, b: &[u8]) -> f32 {
        let v = self.sample_type().decode(b, false);
        match self {
            RawType::U8 => (v / 255.0) as f32,
            RawType::U16 => (v / 65535.0) as f32,
            RawType::I16 => ((v / 32767.0) as f32).max(0.0),
            RawType::F32 | RawType::F64 => v as f32,
        }
    }
}

/// Dimensions and type from an Open SciVis file name such as
/// `bonsai_256x256x256_uint8.raw`.
pub fn parse_scivis_name(path: &Path) -> Option<([u32; 3], RawType)> {
    let stem = path.file_stem()?.to_str()?;
    let mut parts = stem.rsplit('_');
    let ty = RawType::parse(parts.next()?)?;
    let dims: Vec<u32> = parts
        .next()?
        .split('x')
        .map(|s| s.parse().ok())
        .collect::<Option<_>>()?;
    (dims.len() == 3).then(|| ([dims[0], dims[1], dims[2]], ty))
}

/// Reads a raw volume. Explicit `dims`/`ty` win over the file name.
pub fn read_raw(
    path: &Path,
    dims: Option<[u32; 3]>,
    ty: Option<RawType>,
) -> Result<BrickGrid<f32>> {
    let named = parse_scivis_name(path);
    let (dims, ty) = match (dims, ty, named) {
        (Some(d), Some(t), _) => (d, t),
        (Some(d), None, Some((_, t))) => (d, t),
        (None, Some(t), Some((d, _))) => (d, t),
        (None, None, Some(n)) => n,
        _ => return Err(VolumeError::format(
            path,
            "raw volume needs `dims` and `type`, or a file name like `name_256x256x256_uint8.raw`",
        )),
    };
    check_dims(dims.map(u64::from)).map_err(|e| VolumeError::format(path, e.to_string()))?;
    let expected = dims.iter().map(|&d| d as u64).product::<u64>() * ty.bytes() as u64;
    let len = std::fs::metadata(path)
        .map_err(|e| VolumeError::io(path, e))?
        .len();
    if len != expected {
        return Err(VolumeError::format(
            path,
            format!(
                "size {len} bytes does not match {}×{}×{} {:?} ({} bytes)",
                dims[0], dims[1], dims[2], ty, expected
            ),
        ));
    }
    let bytes = std::fs::read(path).map_err(|e| VolumeError::io(path, e))?;
    let (nx, ny) = (dims[0] as usize, dims[1] as usize);
    let s = ty.bytes();
    BrickGrid::from_fn(dims, |i, j, k| {
        let o = ((k as usize * ny + j as usize) * nx + i as usize) * s;
        let v = ty.decode(&bytes[o..o + s]);
        if v.is_finite() {
            v.max(0.0)
        } else {
            0.0
        }
    })
    .map_err(|e| VolumeError::format(path, e.to_string()))
}

#[cfg(test)]
mod raw_test {
    use super::*;

    #[test]
    fn scivis_names() {
        assert_eq!(
            parse_scivis_name(Path::new("a/bonsai_256x256x256_uint8.raw")),
            Some(([256, 256, 256], RawType::U8))
        );
        assert_eq!(
            parse_scivis_name(Path::new("x_1x2x3_float32.raw")),
            Some(([1, 2, 3], RawType::F32))
        );
        assert_eq!(parse_scivis_name(Path::new("plain.raw")), None);
    }

    #[test]
    fn reads_and_validates_size() {
        let dir = std::env::temp_dir().join("fogbank_raw_test");
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t_4x3x2_uint16.raw");
        let vals: Vec<u16> = (0..24).map(|i| i * 1000).collect();
        std::fs::write(
            &p,
            vals.iter()
                .flat_map(|v| v.to_le_bytes())
                .collect::<Vec<u8>>(),
        )
        .unwrap();
        let g = read_raw(&p, None, None).unwrap();
        assert_eq!(g.dims(), [4, 3, 2]);
        assert!((g.fetch(1, 2, 1) - (1 + 4 * 2 + 12) as f32 * 1000.0 / 65535.0).abs() < 1e-6);
        let e = read_raw(&p, Some([5, 5, 5]), None).unwrap_err().to_string();
        assert!(
            e.contains("t_4x3x2_uint16.raw") && e.contains("does not match"),
            "{e}"
        );
    }
}

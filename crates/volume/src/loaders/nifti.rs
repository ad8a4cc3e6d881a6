//! NIfTI-1 and NIfTI-2 (`.nii`, `.nii.gz`, `.hdr` + `.img`): 3D scalar
//! volumes of u8, i8, i16, u16, i32, u32, i64, u64, f32 and f64, either byte
//! order (told by `sizeof_hdr`), gzip by its magic bytes; `scl_slope` and
//! `scl_inter` applied when the slope is finite and non-zero (as nibabel);
//! placement from the sform when `sform_code > 0`, else the qform (the
//! quaternion with qfac from `pixdim[0]`) when `qform_code > 0`, else the
//! voxel spacing — the NIfTI standard's three methods, in nibabel's order.
//! World space is RAS in millimetres. Files with more than three
//! dimensions give one 3D volume, chosen by index (`channel` in a scene).

use super::sample::SampleType;
use super::scalar::{check_volume, decode_samples, read_maybe_gzip, ScalarVolume, MAX_VOXELS};
use crate::{Result, VolumeError};
use fogbank_math::{DAffine3, DVec3};
use glam::DMat3;
use std::path::{Path, PathBuf};

/// The header fields fogbank uses, from either version.
#[derive(Clone, Debug, PartialEq)]
pub struct NiftiHeader {
    pub version: u8,
    pub big_endian: bool,
    /// `dim[1..=dim[0]]`.
    pub dims: Vec<u64>,
    pub datatype: i16,
    pub pixdim: [f64; 8],
    pub vox_offset: f64,
    pub scl_slope: f64,
    pub scl_inter: f64,
    pub qform_code: i32,
    pub sform_code: i32,
    /// quatern_b, c, d.
    pub quatern: [f64; 3],
    pub qoffset: [f64; 3],
    pub srow: [[f64; 4]; 3],
    /// Data in the same file (`n+1`, `n+2`) rather than a `.img`.
    pub single_file: bool,
}

/// Bounds-checked field reads in one byte order.
struct Fields<'a> {
    path: &'a Path,
    b: &'a [u8],
    big: bool,
}

impl Fields<'_> {
    fn get<const N: usize>(&self, at: usize) -> Result<[u8; N]> {
        let mut a: [u8; N] = self
            .b
            .get(at..at + N)
            .and_then(|s| s.try_into().ok())
            .ok_or_else(|| {
                VolumeError::format(self.path, format!("header truncated at byte {at}"))
            })?;
        if self.big {
            a.reverse();
        }
        Ok(a)
    }
    fn i16(&self, at: usize) -> Result<i16> {
        Ok(i16::from_le_bytes(self.get(at)?))
    }
    fn i32(&self, at: usize) -> Result<i32> {
        Ok(i32::from_le_bytes(self.get(at)?))
    }
    fn i64(&self, at: usize) -> Result<i64> {
        Ok(i64::from_le_bytes(self.get(at)?))
    }
    fn f32(&self, at: usize) -> Result<f64> {
        Ok(f32::from_le_bytes(self.get(at)?) as f64)
    }
    fn f64(&self, at: usize) -> Result<f64> {
        Ok(f64::from_le_bytes(self.get(at)?))
    }
}

/// Parses the header at the start of `b` (already decompressed).
pub fn parse_header(path: &Path, b: &[u8]) -> Result<NiftiHeader> {
    let size = |big| Fields { path, b, big }.i32(0);
    let (version, big) = match (size(false)?, size(true)?) {
        (348, _) => (1, false),
        (_, 348) => (1, true),
        (540, _) => (2, false),
        (_, 540) => (2, true),
        (s, _) => {
            return Err(VolumeError::format(
                path,
                format!("not a NIfTI file: sizeof_hdr is {s} (348 for NIfTI-1, 540 for NIfTI-2)"),
            ))
        }
    };
    let f = Fields { path, b, big };
    if version == 1 {
        nifti1(&f)
    } else {
        nifti2(&f)
    }
}

/// The fields of a NIfTI-1 header (348 bytes; offsets from nifti1.h).
fn nifti1(f: &Fields) -> Result<NiftiHeader> {
    let (path, b, version, big) = (f.path, f.b, 1, f.big);
    let magic = |at: usize| b.get(at..at + 4).unwrap_or_default();
    let m = magic(344);
    if m != b"n+1\0" && m != b"ni1\0" {
        return Err(VolumeError::format(
            path,
            "NIfTI-1 magic at byte 344 is not `n+1` or `ni1`",
        ));
    }
    let ndim = f.i16(40)?;
    let dims = dims_of(path, ndim as i64, |i| Ok(f.i16(40 + 2 * i)? as i64))?;
    let mut pixdim = [0.0; 8];
    for (i, p) in pixdim.iter_mut().enumerate() {
        *p = f.f32(76 + 4 * i)?;
    }
    let row = |at: usize| -> Result<[f64; 4]> {
        Ok([f.f32(at)?, f.f32(at + 4)?, f.f32(at + 8)?, f.f32(at + 12)?])
    };
    Ok(NiftiHeader {
        version,
        big_endian: big,
        dims,
        datatype: f.i16(70)?,
        pixdim,
        vox_offset: f.f32(108)?,
        scl_slope: f.f32(112)?,
        scl_inter: f.f32(116)?,
        qform_code: f.i16(252)? as i32,
        sform_code: f.i16(254)? as i32,
        quatern: [f.f32(256)?, f.f32(260)?, f.f32(264)?],
        qoffset: [f.f32(268)?, f.f32(272)?, f.f32(276)?],
        srow: [row(280)?, row(296)?, row(312)?],
        single_file: m == b"n+1\0",
    })
}

/// The fields of a NIfTI-2 header (540 bytes; offsets from nifti2.h).
fn nifti2(f: &Fields) -> Result<NiftiHeader> {
    let (path, b, version, big) = (f.path, f.b, 2, f.big);
    let magic = |at: usize| b.get(at..at + 4).unwrap_or_default();
    let m = magic(4);
    if m != b"n+2\0" && m != b"ni2\0" {
        return Err(VolumeError::format(
            path,
            "NIfTI-2 magic at byte 4 is not `n+2` or `ni2`",
        ));
    }
    let ndim = f.i64(16)?;
    let dims = dims_of(path, ndim, |i| f.i64(16 + 8 * i))?;
    let mut pixdim = [0.0; 8];
    for (i, p) in pixdim.iter_mut().enumerate() {
        *p = f.f64(104 + 8 * i)?;
    }
    let row = |at: usize| -> Result<[f64; 4]> {
        Ok([f.f64(at)?, f.f64(at + 8)?, f.f64(at + 16)?, f.f64(at + 24)?])
    };
    Ok(NiftiHeader {
        version,
        big_endian: big,
        dims,
        datatype: f.i16(12)?,
        pixdim,
        vox_offset: f.i64(168)? as f64,
        scl_slope: f.f64(176)?,
        scl_inter: f.f64(184)?,
        qform_code: f.i32(344)?,
        sform_code: f.i32(348)?,
        quatern: [f.f64(352)?, f.f64(360)?, f.f64(368)?],
        qoffset: [f.f64(376)?, f.f64(384)?, f.f64(392)?],
        srow: [row(400)?, row(432)?, row(464)?],
        single_file: m == b"n+2\0",
    })
}

/// `dim[1..=ndim]`, each ≥ 1, `ndim` in 1..=7.
fn dims_of(path: &Path, ndim: i64, dim: impl Fn(usize) -> Result<i64>) -> Result<Vec<u64>> {
    if !(1..=7).contains(&ndim) {
        return Err(VolumeError::format(
            path,
            format!("dim[0] = {ndim}, not in 1..=7"),
        ));
    }
    (1..=ndim as usize)
        .map(|i| {
            let d = dim(i)?;
            if d < 1 {
                Err(VolumeError::format(
                    path,
                    format!("dim[{i}] = {d}, must be at least 1"),
                ))
            } else {
                Ok(d as u64)
            }
        })
        .collect()
}

impl NiftiHeader {
    pub fn sample_type(&self, path: &Path) -> Result<SampleType> {
        Ok(match self.datatype {
            2 => SampleType::U8,
            4 => SampleType::I16,
            8 => SampleType::I32,
            16 => SampleType::F32,
            64 => SampleType::F64,
            256 => SampleType::I8,
            512 => SampleType::U16,
            768 => SampleType::U32,
            1024 => SampleType::I64,
            1280 => SampleType::U64,
            d => {
                return Err(VolumeError::format(
                    path,
                    format!("datatype {d} is not a supported scalar type (u8, i8, i16, u16, i32, u32, i64, u64, f32, f64)"),
                ))
            }
        })
    }

    /// The three spatial sizes and the number of 3D volumes after them.
    pub fn spatial(&self) -> ([u64; 3], u64) {
        let d = |i: usize| self.dims.get(i).copied().unwrap_or(1);
        // Saturating: a forged header may give sizes whose product overflows.
        let volumes = self
            .dims
            .iter()
            .skip(3)
            .fold(1u64, |a, &d| a.saturating_mul(d));
        ([d(0), d(1), d(2)], volumes.max(1))
    }

    /// Voxel centres at integer indices → world (RAS mm), and where the
    /// map came from.
    pub fn affine(&self, path: &Path) -> Result<(DAffine3, &'static str)> {
        let spacing = |i: usize| {
            let p = self.pixdim[i];
            if p.is_finite() && p != 0.0 {
                p.abs()
            } else {
                1.0
            }
        };
        let (a, from) = if self.sform_code > 0 {
            let r = self.srow;
            let m = DMat3::from_cols(
                DVec3::new(r[0][0], r[1][0], r[2][0]),
                DVec3::new(r[0][1], r[1][1], r[2][1]),
                DVec3::new(r[0][2], r[1][2], r[2][2]),
            );
            (
                DAffine3::from_mat3_translation(m, DVec3::new(r[0][3], r[1][3], r[2][3])),
                "sform",
            )
        } else if self.qform_code > 0 {
            let [mut b, mut c, mut d] = self.quatern;
            let n = b * b + c * c + d * d;
            let a = if n > 1.0 {
                // Rounding in the file: a = 0, (b, c, d) renormalised.
                let s = n.sqrt();
                (b, c, d) = (b / s, c / s, d / s);
                0.0
            } else {
                (1.0 - n).sqrt()
            };
            let r = DMat3::from_cols(
                DVec3::new(
                    a * a + b * b - c * c - d * d,
                    2.0 * (b * c + a * d),
                    2.0 * (b * d - a * c),
                ),
                DVec3::new(
                    2.0 * (b * c - a * d),
                    a * a + c * c - b * b - d * d,
                    2.0 * (c * d + a * b),
                ),
                DVec3::new(
                    2.0 * (b * d + a * c),
                    2.0 * (c * d - a * b),
                    a * a + d * d - c * c - b * b,
                ),
            );
            let qfac = if self.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
            let s = DVec3::new(spacing(1), spacing(2), qfac * spacing(3));
            (
                DAffine3::from_mat3_translation(
                    r * DMat3::from_diagonal(s),
                    DVec3::from(self.qoffset),
                ),
                "qform",
            )
        } else {
            (
                DAffine3::from_scale(DVec3::new(spacing(1), spacing(2), spacing(3))),
                "pixdim (no sform or qform)",
            )
        };
        let det = a.matrix3.determinant();
        if !det.is_finite() || det.abs() < 1e-12 || !a.translation.is_finite() {
            return Err(VolumeError::format(
                path,
                format!("the {from} voxel-to-world map is singular or not finite"),
            ));
        }
        Ok((a, from))
    }
}

/// Decodes a NIfTI file already in memory (decompressed); `img` holds the
/// data of a `.hdr`/`.img` pair (`None` for single files).
pub fn parse(path: &Path, bytes: &[u8], img: Option<&[u8]>, volume: u32) -> Result<ScalarVolume> {
    let h = parse_header(path, bytes)?;
    let ty = h.sample_type(path)?;
    let (dims, volumes) = h.spatial();
    if volume as u64 >= volumes {
        return Err(VolumeError::format(
            path,
            format!("volume index {volume} out of range: the file holds {volumes} 3D volume(s)"),
        ));
    }
    let n = check_volume(path, dims)?;
    let (a, from) = h.affine(path)?;
    let (data, base) = match (h.single_file, img) {
        (true, _) => (bytes, h.vox_offset),
        (false, Some(img)) => (img, h.vox_offset.max(0.0)),
        (false, None) => {
            return Err(VolumeError::format(
                path,
                "a `ni1`/`ni2` header needs its `.img` data file",
            ))
        }
    };
    if !(base >= 0.0 && base.is_finite() && base < MAX_VOXELS as f64 * 8.0) {
        return Err(VolumeError::format(
            path,
            format!("vox_offset {base} is not a valid byte offset"),
        ));
    }
    let offset = (base as usize)
        .checked_add(
            (volume as usize)
                .checked_mul(n * ty.bytes())
                .ok_or_else(|| VolumeError::format(path, "data offset overflows"))?,
        )
        .ok_or_else(|| VolumeError::format(path, "data offset overflows"))?;
    let mut values = decode_samples(path, data, offset, n, ty, h.big_endian)?;
    let scaled = h.scl_slope.is_finite()
        && h.scl_slope != 0.0
        && (h.scl_slope != 1.0 || (h.scl_inter.is_finite() && h.scl_inter != 0.0));
    if scaled {
        let (s, i) = (
            h.scl_slope,
            if h.scl_inter.is_finite() {
                h.scl_inter
            } else {
                0.0
            },
        );
        for v in &mut values {
            *v = (*v as f64 * s + i) as f32;
        }
    }
    Ok(ScalarVolume {
        dims: dims.map(|d| d as u32),
        values,
        index_to_world: ScalarVolume::node_centred(a),
        description: format!(
            "NIfTI-{} ({}-endian), {}, placement from the {from}{}",
            h.version,
            if h.big_endian { "big" } else { "little" },
            ty.name(),
            if scaled {
                format!(", values × {} + {}", h.scl_slope, h.scl_inter)
            } else {
                String::new()
            }
        ),
        sample_type: ty,
    })
}

/// The largest file a NIfTI header can describe that fogbank reads.
const LIMIT: u64 = MAX_VOXELS * 8 + (1 << 20);

/// Reads `.nii`, `.nii.gz` or a `.hdr` (with its `.img` or `.img.gz`).
pub fn read(path: &Path, volume: u32) -> Result<ScalarVolume> {
    let bytes = read_maybe_gzip(path, LIMIT)?;
    let h = parse_header(path, &bytes)?;
    if h.single_file {
        return parse(path, &bytes, None, volume);
    }
    let img = image_file(path).ok_or_else(|| {
        VolumeError::format(
            path,
            "a `ni1` header needs a `.img` (or `.img.gz`) beside it",
        )
    })?;
    let data = read_maybe_gzip(&img, LIMIT)?;
    parse(path, &bytes, Some(&data), volume)
}

fn image_file(hdr: &Path) -> Option<PathBuf> {
    let s = hdr.to_str()?;
    let stem = s.strip_suffix(".gz").unwrap_or(s);
    let stem = stem.strip_suffix(".hdr")?;
    [".img", ".img.gz"]
        .iter()
        .map(|e| PathBuf::from(format!("{stem}{e}")))
        .find(|p| p.exists())
}

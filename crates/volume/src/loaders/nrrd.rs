//! NRRD (`.nrrd` with attached data, `.nhdr` with a detached data file):
//! raw, gzip and ascii encodings, either byte order, `byte skip` (of the
//! decoded stream; −1 for raw data at the end of the file) and `line skip`
//! (of the file); placement from `space directions` and `space origin`
//! (the centre of the first voxel), converted from LPS to RAS so NRRD and
//! NIfTI files share one world (RAS millimetres); `spacings` when there
//! are no directions. Three spatial axes, plus at most one non-spatial
//! axis (`none` direction, e.g. a vector component) chosen by index.

use super::sample::SampleType;
use super::scalar::{check_volume, decode_samples, gunzip, ScalarVolume, MAX_VOXELS};
use crate::{Result, VolumeError};
use fogbank_math::{DAffine3, DVec3};
use glam::DMat3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The header's fields (name → value) and where attached data starts.
#[derive(Clone, Debug)]
pub struct NrrdHeader {
    pub fields: HashMap<String, String>,
    pub data_start: usize,
}

/// Headers longer than this are refused (real ones are a few KiB).
const MAX_HEADER: usize = 1 << 20;

pub fn parse_header(path: &Path, b: &[u8]) -> Result<NrrdHeader> {
    if !b.starts_with(b"NRRD000") {
        return Err(VolumeError::format(
            path,
            "not a NRRD file: it does not start with `NRRD000`",
        ));
    }
    let mut fields = HashMap::new();
    // The first line is the magic; fields follow until an empty line.
    let mut pos = b
        .iter()
        .position(|&c| c == b'\n')
        .map_or(b.len(), |e| e + 1);
    while pos < b.len() {
        if pos >= MAX_HEADER {
            return Err(VolumeError::format(path, "header longer than 1 MiB"));
        }
        let end = b[pos..]
            .iter()
            .position(|&c| c == b'\n')
            .map_or(b.len(), |e| pos + e);
        let line = std::str::from_utf8(&b[pos..end])
            .map_err(|_| {
                VolumeError::format(path, format!("header line at byte {pos} is not text"))
            })?
            .trim_end_matches('\r');
        pos = end + 1;
        if line.is_empty() {
            break;
        }
        if line.starts_with('#') || line.contains(":=") {
            continue;
        }
        let (k, v) = line.split_once(": ").ok_or_else(|| {
            VolumeError::format(path, format!("header line `{line}` is not `field: value`"))
        })?;
        fields.insert(k.trim().to_string(), v.trim().to_string());
    }
    Ok(NrrdHeader {
        fields,
        data_start: pos.min(b.len()),
    })
}

fn sample_type(path: &Path, t: &str) -> Result<SampleType> {
    use SampleType::*;
    Ok(match t {
        "signed char" | "int8" | "int8_t" => I8,
        "uchar" | "unsigned char" | "uint8" | "uint8_t" => U8,
        "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => I16,
        "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => U16,
        "int" | "signed int" | "int32" | "int32_t" => I32,
        "uint" | "unsigned int" | "uint32" | "uint32_t" => U32,
        "longlong"
        | "long long"
        | "long long int"
        | "signed long long"
        | "signed long long int"
        | "int64"
        | "int64_t" => I64,
        "ulonglong" | "unsigned long long" | "unsigned long long int" | "uint64" | "uint64_t" => {
            U64
        }
        "float" => F32,
        "double" => F64,
        other => {
            return Err(VolumeError::format(
                path,
                format!("type `{other}` is not a supported scalar type"),
            ))
        }
    })
}

/// `(x,y,z)` or `none`.
fn vector(path: &Path, s: &str) -> Result<Option<DVec3>> {
    if s == "none" {
        return Ok(None);
    }
    let inner = s
        .strip_prefix('(')
        .and_then(|s| s.strip_suffix(')'))
        .ok_or_else(|| VolumeError::format(path, format!("`{s}` is not a vector `(x,y,z)`")))?;
    let v: Vec<f64> = inner
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| VolumeError::format(path, format!("`{s}` is not a vector of numbers")))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Some(DVec3::new(x, y, z))),
        _ => Err(VolumeError::format(
            path,
            format!("`{s}`: fogbank needs 3D space vectors"),
        )),
    }
}

impl NrrdHeader {
    fn get(&self, path: &Path, k: &str) -> Result<&str> {
        self.fields
            .get(k)
            .map(String::as_str)
            .ok_or_else(|| VolumeError::format(path, format!("header has no `{k}` field")))
    }

    fn int(&self, path: &Path, k: &str, default: i64) -> Result<i64> {
        match self.fields.get(k) {
            None => Ok(default),
            Some(v) => v
                .parse()
                .map_err(|_| VolumeError::format(path, format!("`{k}: {v}` is not an integer"))),
        }
    }

    /// Per-axis sizes, and the direction of each axis (`None`: not spatial).
    fn axes(&self, path: &Path) -> Result<(Vec<u64>, Vec<Option<DVec3>>)> {
        let n: usize = self
            .get(path, "dimension")?
            .parse()
            .ok()
            .filter(|n| (1..=16).contains(n))
            .ok_or_else(|| VolumeError::format(path, "`dimension` must be an integer in 1..=16"))?;
        let sizes: Vec<u64> = self
            .get(path, "sizes")?
            .split_whitespace()
            .map(|s| s.parse::<u64>().ok().filter(|&d| d >= 1))
            .collect::<Option<_>>()
            .ok_or_else(|| VolumeError::format(path, "`sizes` must be positive integers"))?;
        if sizes.len() != n {
            return Err(VolumeError::format(
                path,
                format!("`sizes` has {} entries for dimension {n}", sizes.len()),
            ));
        }
        let dirs: Vec<Option<DVec3>> = if let Some(d) = self.fields.get("space directions") {
            let parts = split_vectors(d);
            if parts.len() != n {
                return Err(VolumeError::format(
                    path,
                    format!(
                        "`space directions` has {} entries for dimension {n}",
                        parts.len()
                    ),
                ));
            }
            parts
                .iter()
                .map(|p| vector(path, p))
                .collect::<Result<_>>()?
        } else {
            let sp: Vec<f64> = match self.fields.get("spacings") {
                Some(s) => s
                    .split_whitespace()
                    .map(|x| x.parse::<f64>().unwrap_or(f64::NAN))
                    .collect(),
                None => vec![1.0; n],
            };
            let spatial = n.min(3);
            (0..n)
                .map(|i| {
                    (i >= n - spatial).then(|| {
                        let s = sp
                            .get(i)
                            .copied()
                            .filter(|s| s.is_finite() && *s != 0.0)
                            .unwrap_or(1.0);
                        let mut v = DVec3::ZERO;
                        v[i + spatial - n] = s;
                        v
                    })
                })
                .collect()
        };
        Ok((sizes, dirs))
    }
}

/// Splits `(1,0,0) (0,1,0) none` into its entries.
fn split_vectors(s: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut depth = 0;
    for c in s.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ => {}
        }
        if c.is_whitespace() && depth == 0 {
            if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
        } else if !(c.is_whitespace() && depth > 0) {
            cur.push(c);
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Whether the samples are big-endian (`endian`, which multi-byte binary
/// data must give).
fn big_endian(path: &Path, h: &NrrdHeader, ty: SampleType) -> Result<bool> {
    let big = match h.fields.get("endian").map(String::as_str) {
        Some("big") => true,
        Some("little") | None => false,
        Some(e) => {
            return Err(VolumeError::format(
                path,
                format!("endian `{e}` is not little or big"),
            ))
        }
    };
    if ty.bytes() > 1
        && !h.fields.contains_key("endian")
        && h.fields.get("encoding").map(String::as_str) != Some("ascii")
    {
        return Err(VolumeError::format(
            path,
            "multi-byte data needs an `endian` field",
        ));
    }
    Ok(big)
}

/// The `total` samples of type `ty` in `file` after its `line skip` and
/// `byte skip`, decoded from its `encoding` (raw, gzip or ascii).
fn samples(
    path: &Path,
    h: &NrrdHeader,
    file: &[u8],
    total: u64,
    ty: SampleType,
    big: bool,
) -> Result<Vec<f32>> {
    let line_skip = h.int(path, "line skip", 0)?.max(0) as usize;
    let mut file = file;
    for _ in 0..line_skip {
        let e = file
            .iter()
            .position(|&c| c == b'\n')
            .ok_or_else(|| VolumeError::format(path, "`line skip` passes the end of the data"))?;
        file = &file[e + 1..];
    }
    let byte_skip = h.int(path, "byte skip", 0)?;
    let need = total * ty.bytes() as u64;
    let encoding = h.get(path, "encoding")?;
    Ok(match encoding {
        "raw" => {
            let start = if byte_skip == -1 {
                file.len().checked_sub(need as usize).ok_or_else(|| {
                    VolumeError::format(
                        path,
                        format!("data is {} bytes, {need} needed", file.len()),
                    )
                })?
            } else {
                byte_skip.max(0) as usize
            };
            decode_samples(path, file, start, total as usize, ty, big)?
        }
        "gzip" | "gz" => {
            let skip = byte_skip.max(0) as u64;
            let bytes = gunzip(path, file, need + skip)?;
            decode_samples(path, &bytes, skip as usize, total as usize, ty, big)?
        }
        "ascii" | "text" | "txt" => {
            let text = std::str::from_utf8(file)
                .map_err(|_| VolumeError::format(path, "ascii data is not text"))?;
            let v: Vec<f32> = text
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|s| !s.is_empty())
                .take(total as usize)
                .map(|s| s.parse::<f64>().map(|x| x as f32))
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| VolumeError::format(path, "ascii data holds a non-number"))?;
            if v.len() as u64 != total {
                return Err(VolumeError::format(
                    path,
                    format!("ascii data holds {} numbers, {total} needed", v.len()),
                ));
            }
            v
        }
        e => {
            return Err(VolumeError::format(
                path,
                format!("encoding `{e}` is not supported (raw, gzip, ascii)"),
            ))
        }
    })
}

/// Decodes a NRRD whose header is in `header_bytes` and whose data is
/// attached there or in `detached` (the data file's bytes, as read).
pub fn parse(
    path: &Path,
    header_bytes: &[u8],
    detached: Option<&[u8]>,
    index: u32,
) -> Result<ScalarVolume> {
    let h = parse_header(path, header_bytes)?;
    let ty = sample_type(path, h.get(path, "type")?)?;
    let (sizes, dirs) = h.axes(path)?;
    let spatial: Vec<usize> = (0..sizes.len()).filter(|&i| dirs[i].is_some()).collect();
    let other: Vec<usize> = (0..sizes.len()).filter(|&i| dirs[i].is_none()).collect();
    if spatial.len() != 3 || other.len() > 1 {
        return Err(VolumeError::format(
            path,
            format!(
                "fogbank reads 3 spatial axes and at most one other; this file has {} and {}",
                spatial.len(),
                other.len()
            ),
        ));
    }
    let count = other.first().map_or(1, |&a| sizes[a]);
    if index as u64 >= count {
        return Err(VolumeError::format(
            path,
            format!("index {index} out of range: the non-spatial axis has {count} entries"),
        ));
    }
    let dims = [sizes[spatial[0]], sizes[spatial[1]], sizes[spatial[2]]];
    let n = check_volume(path, dims)?;
    // Saturating: `sizes` of a forged header may overflow the product.
    let total = (n as u64).saturating_mul(count);
    if total > MAX_VOXELS {
        return Err(VolumeError::format(
            path,
            format!("{total} samples, more than the limit of {MAX_VOXELS}"),
        ));
    }
    let big = big_endian(path, &h, ty)?;
    let file = match detached {
        Some(d) => d,
        None => &header_bytes[h.data_start..],
    };
    let encoding = h.get(path, "encoding")?;
    let all = samples(path, &h, file, total, ty, big)?;
    let values = match other.first() {
        None => all,
        Some(&a) => extract(&sizes, a, index as u64, &all),
    };
    let a = placement(path, &h, &spatial, &dirs)?;
    Ok(ScalarVolume {
        dims: dims.map(|d| d as u32),
        values,
        index_to_world: ScalarVolume::node_centred(a),
        description: format!(
            "NRRD, {}, {encoding}, {}-endian, space `{}`",
            ty.name(),
            if big { "big" } else { "little" },
            h.fields.get("space").map_or("none", String::as_str)
        ),
        sample_type: ty,
    })
}

/// The samples with entry `index` on axis `a` (the others keep their order).
fn extract(sizes: &[u64], a: usize, index: u64, all: &[f32]) -> Vec<f32> {
    let inner: u64 = sizes[..a].iter().product();
    let len = sizes[a];
    let outer: u64 = sizes[a + 1..].iter().product();
    let mut out = Vec::with_capacity((inner * outer) as usize);
    for o in 0..outer {
        let base = ((o * len + index) * inner) as usize;
        out.extend_from_slice(&all[base..base + inner as usize]);
    }
    out
}

/// Voxel centres at integer indices → RAS world.
fn placement(
    path: &Path,
    h: &NrrdHeader,
    spatial: &[usize],
    dirs: &[Option<DVec3>],
) -> Result<DAffine3> {
    let d: Vec<DVec3> = spatial.iter().map(|&i| dirs[i].unwrap()).collect();
    let origin = match h.fields.get("space origin") {
        Some(o) => {
            vector(path, o)?.ok_or_else(|| VolumeError::format(path, "`space origin` is `none`"))?
        }
        None => DVec3::ZERO,
    };
    let lps = matches!(
        h.fields.get("space").map(String::as_str),
        Some("left-posterior-superior" | "LPS" | "left-posterior-superior-time" | "LPST")
    );
    let flip = if lps {
        DVec3::new(-1.0, -1.0, 1.0)
    } else {
        DVec3::ONE
    };
    let m = DMat3::from_cols(d[0] * flip, d[1] * flip, d[2] * flip);
    let det = m.determinant();
    if !det.is_finite() || det.abs() < 1e-12 {
        return Err(VolumeError::format(path, "`space directions` are singular"));
    }
    Ok(DAffine3::from_mat3_translation(m, origin * flip))
}

/// The largest data file fogbank reads.
const LIMIT: u64 = MAX_VOXELS * 8 + (1 << 20);

/// Reads `.nrrd` (attached or detached data) or `.nhdr`.
pub fn read(path: &Path, index: u32) -> Result<ScalarVolume> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(LIMIT).read_to_end(&mut head))
        .map_err(|e| VolumeError::io(path, e))?;
    let h = parse_header(path, &head)?;
    match h.fields.get("data file") {
        None => parse(path, &head, None, index),
        Some(f) => {
            if f.starts_with("LIST") || f.contains('%') {
                return Err(VolumeError::format(
                    path,
                    format!("`data file: {f}`: lists and patterns of data files are not supported"),
                ));
            }
            let data = data_path(path, f);
            let bytes = std::fs::read(&data).map_err(|e| VolumeError::io(&data, e))?;
            parse(path, &head, Some(&bytes), index)
        }
    }
}

fn data_path(header: &Path, f: &str) -> PathBuf {
    let p = Path::new(f);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        header.parent().unwrap_or(Path::new(".")).join(p)
    }
}

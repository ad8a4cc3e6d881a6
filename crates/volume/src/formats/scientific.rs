//! What NIfTI and NRRD share: a scalar volume placed in RAS millimetres,
//! its value range mapped onto [0, 1] (a transfer function's points, in
//! file units, mapped the same way), described with a histogram.

use super::describe::{print_transform, say};
use super::format::{Described, FieldData, FileSource, Footprint};
use crate::loaders::scalar::ScalarVolume;
use crate::{DensityData, Precision};
use std::path::Path;

/// A format's reader: the 3D volume `index` of a file.
pub(crate) type Reader = fn(&Path, u32) -> crate::Result<ScalarVolume>;

/// A NIfTI or NRRD volume, its value range mapped onto [0, 1].
pub(crate) fn read(s: &FileSource, precision: Precision, read: Reader) -> crate::Result<FieldData> {
    let v = read(s.path, s.channel.unwrap_or(0)).map_err(|e| s.error(e))?;
    let grid = v.normalised_grid().map_err(|e| s.error(e))?;
    Ok(FieldData {
        units: Some(v.range().unwrap_or((0.0, 1.0))),
        ..FieldData::new(
            DensityData::from_f32(grid, precision),
            v.index_to_world,
            format!("{} ({})", s.path.display(), v.description),
        )
    })
}

/// NIfTI / NRRD: format, sample type, placement, value range and a
/// 16-bin histogram of the file's values (in file units).
pub(crate) fn describe(
    out: &mut String,
    file: &Path,
    footprint: Footprint,
    read: Reader,
) -> Described {
    let v = read(file, 0)?;
    say!(
        out,
        "{}: {}×{}×{}, {}",
        file.display(),
        v.dims[0],
        v.dims[1],
        v.dims[2],
        v.description
    );
    match v.range() {
        Some((lo, hi)) => {
            let non_zero = v.values.iter().filter(|x| **x != 0.0).count();
            say!(
                out,
                "  value range [{lo}, {hi}], {non_zero} non-zero voxels"
            );
            let h = v.histogram(16);
            let peak = h.iter().copied().max().unwrap_or(1).max(1);
            let w = (hi - lo) / 16.0;
            for (i, c) in h.iter().enumerate() {
                let bar = "#".repeat(((*c as f64 / peak as f64) * 40.0).ceil() as usize);
                say!(
                    out,
                    "  [{:>12.4}, {:>12.4}) {c:>10} {bar}",
                    lo + i as f32 * w,
                    lo + (i + 1) as f32 * w
                );
            }
        }
        None => say!(out, "  no finite values"),
    }
    print_transform(out, &v.index_to_world);
    footprint(out, v.normalised_grid()?);
    Ok(())
}

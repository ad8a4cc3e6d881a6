//! Headerless raw voxels (`raw = "f.raw"`) in the unit box: `dims = [x, y,
//! z]` and `type` = u8, u16, i16, f32 or f64, or both from a
//! `name_XxYxZ_uint8.raw` file name; integer types normalised to [0, 1].
//! The size is given, so the extension alone does not tell the format.

use crate::VolumeError;
use super::describe::{print_transform, range_and_sum, say};
use super::format::{Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery};
use crate::loaders::raw;
use crate::medium::unit_box_transform;
use crate::{DensityData, Precision};

pub const FORMAT: VolumeFormat = VolumeFormat {
    key: "raw",
    name: "raw",
    extensions: &[".raw"],
    by_extension: false,
    read,
    describe,
    sparse: None,
    write: None,
};

/// A headerless raw file in the unit box.
fn read(s: &FileSource, precision: Precision) -> crate::Result<FieldData> {
    let ty = match s.ty {
        Some(t) => Some(raw::RawType::parse(t).ok_or_else(|| {
            VolumeError::Invalid(format!(
                "{}.type: unknown raw type `{t}` (u8, u16, i16, f32, f64)",
                s.key
            ))
        })?),
        None => None,
    };
    let grid = raw::read_raw(s.path, s.dims, ty).map_err(|e| s.error(e))?;
    let xf = unit_box_transform(grid.dims());
    Ok(FieldData::new(
        DensityData::from_f32(grid, precision),
        xf,
        s.path.display().to_string(),
    ))
}

/// A raw grid (`--dims`, `--type` when its name does not say).
fn describe(out: &mut String, a: &VolumeQuery, footprint: Footprint) -> Described {
    let dims = a.dims;
    let ty = match &a.ty {
        Some(t) => {
            Some(raw::RawType::parse(t).ok_or_else(|| format!("--type: unknown raw type `{t}`"))?)
        }
        None => None,
    };
    let g = raw::read_raw(&a.file, dims, ty)?;
    let d = g.dims();
    let values =
        (0..d[2]).flat_map(|k| (0..d[1]).flat_map(move |j| (0..d[0]).map(move |i| (i, j, k))));
    let (lo, hi, s) = range_and_sum(values.map(|(i, j, k)| g.fetch(i as i32, j as i32, k as i32)));
    say!(
        out,
        "{}: raw {}×{}×{} (values normalised to [0, 1] for integer types)",
        a.file.display(),
        d[0],
        d[1],
        d[2]
    );
    let non_zero = (0..d[2])
        .flat_map(|k| (0..d[1]).flat_map(move |j| (0..d[0]).map(move |i| (i, j, k))))
        .filter(|&(i, j, k)| g.fetch(i as i32, j as i32, k as i32) != 0.0)
        .count();
    say!(
        out,
        "  value range [{lo}, {hi}], sum {s:.6}, {non_zero} non-zero voxels"
    );
    print_transform(out, &unit_box_transform(d));
    footprint(out, g);
    Ok(())
}


//! Mitsuba's `.vol` (`vol = "f.vol"`): a dense float grid of one or more
//! channels in a bounding box; `channel` (default 0; a 3-channel file
//! without it is an RGB field, Mitsuba's convention for albedo).

use super::describe::{print_transform, range_and_sum, say};
use super::format::{Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery};
use crate::loaders::vol;
use crate::{DensityData, Precision};

pub const FORMAT: VolumeFormat = VolumeFormat {
    key: "vol",
    name: "Mitsuba .vol",
    extensions: &[".vol"],
    by_extension: true,
    read,
    describe,
    sparse: None,
    write: None,
};

/// A `.vol` file's channel.
fn read(s: &FileSource, precision: Precision) -> crate::Result<FieldData> {
    let v = vol::read_vol(s.path).map_err(|e| s.error(e))?;
    let grid = v
        .channel_grid(s.channel.unwrap_or(0))
        .map_err(|e| s.error(e))?
        .map_values(|x| x.max(0.0));
    Ok(FieldData::new(
        DensityData::from_f32(grid, precision),
        v.index_to_world(),
        s.path.display().to_string(),
    ))
}

/// A Mitsuba `.vol` grid, channel by channel.
fn describe(out: &mut String, a: &VolumeQuery, footprint: Footprint) -> Described {
    let v = vol::read_vol(&a.file)?;
    say!(
        out,
        "{}: Mitsuba .vol, {}×{}×{}, {} channel(s), float32, bbox {:?} – {:?}",
        a.file.display(),
        v.dims[0],
        v.dims[1],
        v.dims[2],
        v.channels,
        v.bbox_min,
        v.bbox_max
    );
    for c in 0..v.channels {
        let (lo, hi, s) = range_and_sum(
            v.data
                .iter()
                .skip(c as usize)
                .step_by(v.channels as usize)
                .copied(),
        );
        let channel = v.data.iter().skip(c as usize).step_by(v.channels as usize);
        let non_zero = channel.filter(|x| **x != 0.0).count();
        say!(
            out,
            "  channel {c}: range [{lo}, {hi}], sum {s:.6}, {non_zero} non-zero voxels"
        );
    }
    print_transform(out, &v.index_to_world());
    footprint(out, v.channel_grid(0)?);
    Ok(())
}


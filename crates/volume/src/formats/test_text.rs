//! `test_text` (test-only): a volume format that exists to show what adding
//! one takes — this file and one line of `volume_formats!`. A text file
//! (`.fbtxt`): `X Y Z`, then X·Y·Z values, x fastest, in the unit box.

use super::describe::{print_transform, say};
use super::format::{Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery};
use crate::medium::unit_box_transform;
use crate::{BrickGrid, DensityData, Precision};
use std::path::Path;

pub const FORMAT: VolumeFormat = VolumeFormat {
    key: "test_text",
    name: "fogbank test text",
    extensions: &[".fbtxt"],
    by_extension: true,
    read,
    describe,
    sparse: None,
    write: None,
};

/// The grid of a `.fbtxt` file, its dimensions checked before allocating.
fn grid(path: &Path) -> Result<BrickGrid<f32>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut words = text.split_whitespace();
    let mut dim = || -> Result<u32, String> {
        let w = words.next().ok_or("missing dimensions")?;
        w.parse().map_err(|_| format!("`{w}` is not a dimension"))
    };
    let dims = [dim()?, dim()?, dim()?];
    let n = dims.iter().map(|&d| d as u64).product::<u64>();
    let values: Vec<f32> = words.map(|w| w.parse().unwrap_or(f32::NAN)).collect();
    if values.len() as u64 != n || values.iter().any(|v| !v.is_finite()) {
        return Err(format!("{}: expected {n} finite values", path.display()));
    }
    let [x, y] = [dims[0] as usize, dims[1] as usize];
    let at = |i, j, k| values[i as usize + x * (j as usize + y * k as usize)];
    BrickGrid::from_fn(dims, at).map_err(|e| e.to_string())
}

fn read(s: &FileSource, precision: Precision) -> crate::Result<FieldData> {
    let g = grid(s.path).map_err(|e| s.error(e))?;
    let xf = unit_box_transform(g.dims());
    let data = DensityData::from_f32(g, precision);
    Ok(FieldData::new(data, xf, s.path.display().to_string()))
}

fn describe(out: &mut String, a: &VolumeQuery, footprint: Footprint) -> Described {
    let g = grid(&a.file)?;
    let d = g.dims();
    say!(out, "{}: test text {}×{}×{}", a.file.display(), d[0], d[1], d[2]);
    print_transform(out, &unit_box_transform(d));
    footprint(out, g);
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::formats::{self, FileSource, VolumeQuery};
    use crate::{DensityData, Precision};

    #[test]
    fn a_registered_format_is_told_read_and_described() {
        let dir = std::env::temp_dir().join(format!("fogbank-test-text-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("ramp.fbtxt");
        let values: Vec<String> = (0..64).map(|i| format!("{}", (i % 4) as f32)).collect();
        std::fs::write(&file, format!("4 4 4\n{}", values.join(" "))).unwrap();
        // Told by its key and its extension, named in what readers expect.
        let format = formats::by_key("test_text").expect("registered in one line");
        assert_eq!(formats::by_extension(&file).map(|f| f.key), Some("test_text"));
        assert!(formats::expected_extensions().contains(".fbtxt"));
        // Read as a scene's field reads it (`{ test_text = "ramp.fbtxt" }`).
        let source = FileSource {
            key: "media.0.density",
            path: &file,
            grid: None,
            level_set: None,
            channel: None,
            dims: None,
            ty: None,
        };
        let f = (format.read)(&source, Precision::F32).unwrap();
        let DensityData::F32(g) = &f.data else {
            panic!("f32 voxels")
        };
        assert_eq!((g.dims(), g.fetch(3, 0, 0), g.fetch(2, 3, 3)), ([4; 3], 3.0, 2.0));
        // `fogbank info`'s description, the footprint the caller's.
        let mut out = String::new();
        let query = VolumeQuery {
            file: file.clone(),
            ..Default::default()
        };
        (format.describe)(&mut out, &query, &|o, g| {
            o.push_str(&format!("footprint {:?}\n", g.dims()))
        })
        .unwrap();
        assert!(out.contains("test text 4×4×4") && out.contains("footprint [4, 4, 4]"), "{out}");
        // Bad input is an error naming the key.
        std::fs::write(&file, "4 4").unwrap();
        let e = (format.read)(&source, Precision::F32).err().unwrap().to_string();
        assert!(e.starts_with("media.0.density: "), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

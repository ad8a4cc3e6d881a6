//! `fogbank info FILE` as a library call: what a volume file holds — its
//! format, grids, value range, placement — and what fogbank would make of
//! it (its brick grid's memory, the default pin grid), as the text the
//! command prints.

use crate::error::Error;
use fogbank_math::DAffine3;
use fogbank_render::integrators::shared::pin_params::PinGridParams;
use fogbank_scene::convert::{extensions, FileKind};
use fogbank_volume::loaders::{nanovdb, raw, vdb, vdb_grid, vol};
use fogbank_volume::{BrickGrid, DensityData, Precision};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The file to describe, with what a raw file's name may not say.
#[derive(Clone, Debug, Default)]
pub struct VolumeQuery {
    pub file: PathBuf,
    /// Raw files: dimensions X Y Z (else parsed from `name_XxYxZ_type.raw`).
    pub dims: Option<[u32; 3]>,
    /// Raw files: u8, u16, i16, f32, f64.
    pub ty: Option<String>,
}

/// What `fogbank info` prints about `query.file`; an error naming the file
/// when it cannot be read.
pub fn describe_volume(query: &VolumeQuery) -> Result<String, Error> {
    let mut out = String::new();
    describe_into(&mut out, query).map_err(|e| Error::from_message(e.to_string()))?;
    Ok(out)
}

type Described = Result<(), Box<dyn std::error::Error>>;

/// `writeln!` into the description; writing into a `String` cannot fail.
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {{
        let _ = writeln!($out, $($arg)*);
    }};
}

fn print_transform(out: &mut String, m: &DAffine3) {
    let c = m.matrix3;
    let t = m.translation;
    say!(out, "  transform (index → world):");
    for r in 0..3 {
        say!(
            out,
            "    [{:>12.6} {:>12.6} {:>12.6} | {:>12.6}]",
            c.x_axis[r],
            c.y_axis[r],
            c.z_axis[r],
            t[r]
        );
    }
}

fn print_memory(out: &mut String, grid: BrickGrid<f32>) {
    let dims = grid.dims();
    let voxels = dims.iter().map(|&d| d as f64).product::<f64>();
    let d16 = DensityData::from_f32(grid, Precision::F16);
    let bytes = d16.memory_bytes();
    let (dense, total) = match &d16 {
        DensityData::F16(g) => (g.dense_bricks(), g.brick_count()),
        _ => (0, 0),
    };
    say!(
            out,
        "  fogbank grid: {}×{}×{} voxels, {dense}/{total} dense 8³ bricks, {:.1} MiB as f16 ({:.3} bytes/voxel)",
        dims[0],
        dims[1],
        dims[2],
        bytes as f64 / (1 << 20) as f64,
        bytes as f64 / voxels
    );
    // Hansen 2025's default pin grid for this volume (0.1× the f16 texture).
    let g = PinGridParams::default();
    let p = g.positions_for(voxels as u64);
    let pins = (p as u64).pow(3) * (g.phi * g.theta) as u64;
    say!(
            out,
        "  pin grid (pins = \"ms\", default): {p}³ positions × {} directions = {pins} pins, {:.2} MiB",
        g.phi * g.theta,
        (pins * 8) as f64 / (1 << 20) as f64
    );
}

fn range_and_sum(values: impl Iterator<Item = f32>) -> (f32, f32, f64) {
    values.fold((f32::INFINITY, f32::NEG_INFINITY, 0.0), |(lo, hi, s), v| {
        (lo.min(v), hi.max(v), s + v as f64)
    })
}

fn describe_into(out: &mut String, a: &VolumeQuery) -> Described {
    let name = a.file.to_string_lossy().to_ascii_lowercase();
    match FileKind::of(&a.file) {
        Some(FileKind::Volume("nifti")) => scientific_info(out, &a.file, true),
        Some(FileKind::Volume("nrrd")) => scientific_info(out, &a.file, false),
        Some(FileKind::Volume("vdb")) => grid_file_info(out, a, &OPENVDB),
        Some(FileKind::Volume("nvdb")) => grid_file_info(out, a, &NANOVDB),
        Some(FileKind::Volume("vol")) => vol_info(out, a),
        _ if name.ends_with(".raw") => raw_info(out, a),
        _ => Err(format!(
            "{}: unknown volume format (expected {}, or .raw)",
            a.file.display(),
            extensions(|k| !k.is_scene())
        )
        .into()),
    }
}

/// A file format of sparse grids (OpenVDB, NanoVDB): its readers and how
/// it names its versions.
struct GridFormat {
    name: &'static str,
    list: fn(&Path) -> fogbank_volume::Result<Vec<vdb::VdbGridDescriptor>>,
    read: fn(&Path, Option<&str>) -> fogbank_volume::Result<vdb::VdbGrid>,
    version: fn(u32) -> String,
}

const OPENVDB: GridFormat = GridFormat {
    name: "OpenVDB",
    list: vdb::list_grids,
    read: vdb::read_grid,
    version: |v| format!("file version {v}"),
};

const NANOVDB: GridFormat = GridFormat {
    name: "NanoVDB",
    list: nanovdb::list_grids,
    read: nanovdb::read_grid,
    version: |v| format!("NanoVDB {}", nanovdb::version_string(v)),
};

/// Every grid of an OpenVDB or NanoVDB file.
fn grid_file_info(out: &mut String, a: &VolumeQuery, format: &GridFormat) -> Described {
    let grids = (format.list)(&a.file)?;
    say!(
        out,
        "{}: {}, {} grid(s)",
        a.file.display(),
        format.name,
        grids.len()
    );
    for d in grids {
        say!(
            out,
            "grid `{}`: {} ({:?}){}",
            d.name,
            d.value_type,
            d.grid_class,
            if d.supported {
                ""
            } else {
                " — not a float scalar grid, skipped"
            }
        );
        if !d.supported {
            continue;
        }
        let g = (format.read)(&a.file, Some(&d.name))?;
        say!(
            out,
            "  {}, stored as {}, compression {}",
            (format.version)(g.file_version),
            if g.stored_as_half { "half" } else { "float" },
            g.compression
        );
        match g.active_bbox() {
            Some((lo, hi)) => say!(
                out,
                "  index bbox [{}, {}, {}] – [{}, {}, {}]",
                lo[0],
                lo[1],
                lo[2],
                hi[0],
                hi[1],
                hi[2]
            ),
            None => say!(out, "  index bbox: empty"),
        }
        say!(out, "  active voxels {}", g.active_voxel_count());
        if let Some((lo, hi)) = g.active_value_range() {
            say!(
                out,
                "  active value range [{lo}, {hi}], sum {:.6}",
                g.active_value_sum()
            );
        }
        say!(
            out,
            "  background {}, {} leaves, {} tiles",
            g.background,
            g.leaves.len(),
            g.tiles.len()
        );
        let (grid, xf) = vdb_grid::to_brick_grid(g)?;
        print_transform(out, &xf);
        print_memory(out, grid);
    }
    Ok(())
}

/// A Mitsuba `.vol` grid, channel by channel.
fn vol_info(out: &mut String, a: &VolumeQuery) -> Described {
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
    print_memory(out, v.channel_grid(0)?);
    Ok(())
}

/// A raw grid (`--dims`, `--type` when its name does not say).
fn raw_info(out: &mut String, a: &VolumeQuery) -> Described {
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
    print_transform(out, &fogbank_volume::medium::unit_box_transform(d));
    print_memory(out, g);
    Ok(())
}

/// NIfTI / NRRD: format, sample type, placement, value range and a
/// 16-bin histogram of the file's values (in file units).
fn scientific_info(out: &mut String, file: &Path, nifti: bool) -> Described {
    use fogbank_volume::loaders::{nifti as nii, nrrd};
    let v = if nifti {
        nii::read(file, 0)?
    } else {
        nrrd::read(file, 0)?
    };
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
    print_memory(out, v.normalised_grid()?);
    Ok(())
}

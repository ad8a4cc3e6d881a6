//! What OpenVDB (`.vdb`) and NanoVDB (`.nvdb`) share: sparse float grids
//! read leaf by leaf into bricks, level sets read as fog unless `level_set
//! = "raw"`, every grid described, the grid written as it is stored.

use super::describe::{print_transform, say};
use super::format::{Described, FileSource, Footprint, VolumeQuery};
use crate::loaders::{vdb, vdb_grid};
use crate::VolumeError;
use std::path::Path;

/// Whether a grid is read as a fog volume from a level set (`level_set =
/// "fog"`, the default) rather than as its raw values (`"raw"`).
pub(crate) fn level_set_mode(s: &FileSource, g: &vdb::VdbGrid) -> crate::Result<bool> {
    let level_set = vdb_grid::is_level_set(g);
    let mode = s.level_set.unwrap_or("fog");
    if level_set && mode != "fog" && mode != "raw" {
        return Err(VolumeError::Invalid(format!(
            "{}.level_set: `{mode}` is not `fog` or `raw`",
            s.key
        )));
    }
    Ok(level_set && mode == "fog")
}

/// The map of a grid's values to densities: a level set's fog, or the
/// values clamped to be non-negative.
pub(crate) fn value_map(g: &vdb::VdbGrid, to_fog: bool) -> impl Fn(f32) -> f32 + Sync + Copy {
    let fog = vdb_grid::level_set_fog(g.background);
    move |v: f32| if to_fog { fog(v) } else { v.max(0.0) }
}

/// A file format of sparse grids (OpenVDB, NanoVDB): its readers and how
/// it names its versions.
pub(crate) struct GridFormat {
    pub(crate) name: &'static str,
    pub(crate) list: fn(&Path) -> crate::Result<Vec<vdb::VdbGridDescriptor>>,
    pub(crate) read: fn(&Path, Option<&str>) -> crate::Result<vdb::VdbGrid>,
    pub(crate) version: fn(u32) -> String,
}

/// Every grid of an OpenVDB or NanoVDB file.
pub(crate) fn grid_file_info(
    out: &mut String,
    a: &VolumeQuery,
    footprint: Footprint,
    format: &GridFormat,
) -> Described {
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
        footprint(out, grid);
    }
    Ok(())
}

//! The NanoVDB writer against the reader and against NanoVDB's own tools:
//! every file written (Float, Fp8, Fp16 × none, ZIP, BLOSC; a procedural
//! cloud and the dragon) reads back in fogbank's reader (Float exactly,
//! quantised values within half a quantum); and, when Debian's
//! `libnanovdb-tools` are installed, passes `nanovdb_validate`,
//! `nanovdb_print` reports its active voxel count and index box, and
//! `nanovdb_convert` turns it into a `.vdb` whose voxels fogbank's OpenVDB
//! reader reads back. The tool checks skip with a message without the
//! tools, unless `FOGBANK_REQUIRE_NANOVDB=1` (set by `.ci/run`).

use std::path::{Path, PathBuf};
use std::process::Command;

use fogbank_math::sample_data;
use fogbank_math::testdata::tool_on_path;
use fogbank_math::DAffine3;
use fogbank_volume::loaders::nanovdb;
use fogbank_volume::loaders::vdb::{self, VdbGrid};
use fogbank_volume::procedural::cloud_grid;
use fogbank_volume::writers::{self, Codec, NanoOptions, NanoValue};

fn cloud() -> VdbGrid {
    let g = cloud_grid::<f32>(40, 7).unwrap();
    let xf = DAffine3::from_cols_array(&[
        0.02, 0.01, 0.0, 0.0, 0.03, 0.0, 0.0, 0.0, 0.025, 1.0, -2.0, 0.5,
    ]);
    writers::from_brick_grid(&g, xf, "density", 0.0)
}

fn sources() -> Vec<(&'static str, VdbGrid)> {
    vec![
        ("cloud", cloud()),
        (
            "dragon",
            vdb::read_grid(&sample_data::committed("dragon.vdb"), None).unwrap(),
        ),
    ]
}

fn all_options() -> Vec<NanoOptions> {
    let mut out = Vec::new();
    for value in [NanoValue::Float, NanoValue::Fp8, NanoValue::Fp16] {
        for codec in [Codec::None, Codec::Zip, Codec::Blosc] {
            out.push(NanoOptions { value, codec });
        }
    }
    out
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `back` holds `g`'s voxels: same leaves and masks (any order), values
/// equal (Float) or within half a quantum of the leaf's value range.
fn assert_close(back: &VdbGrid, g: &VdbGrid, value: NanoValue, ctx: &str) {
    assert_eq!(back.background, g.background, "{ctx}");
    assert_eq!(back.tiles.len(), g.tiles.len(), "{ctx}");
    assert_eq!(back.leaves.len(), g.leaves.len(), "{ctx}");
    let levels = match value {
        NanoValue::Float => 0.0,
        NanoValue::Fp8 => 255.0,
        NanoValue::Fp16 => 65535.0,
    };
    for leaf in &g.leaves {
        let b = back.leaves.iter().find(|b| b.origin == leaf.origin);
        let b = b.unwrap_or_else(|| panic!("{ctx}: no leaf at {:?}", leaf.origin));
        assert_eq!(b.active, leaf.active, "{ctx}: mask of {:?}", leaf.origin);
        let lo = leaf.values.iter().copied().fold(f32::MAX, f32::min);
        let hi = leaf.values.iter().copied().fold(f32::MIN, f32::max);
        let tol = if levels > 0.0 {
            // Half a quantum, and the rounding of `code · quantum + min`.
            0.5 * (hi - lo) / levels + 4.0 * f32::EPSILON * hi.abs().max(lo.abs())
        } else {
            0.0
        };
        for (x, y) in b.values.iter().zip(leaf.values.iter()) {
            assert!(
                (x - y).abs() <= tol,
                "{ctx}: {x} vs {y} in {:?}",
                leaf.origin
            );
        }
    }
}

#[test]
fn written_nvdb_reads_back() {
    let dir = temp_dir("fogbank_nvdb_write");
    for (name, g) in sources() {
        for o in all_options() {
            let path = dir.join(format!("{name}-{:?}-{}.nvdb", o.value, o.codec.name()));
            writers::nanovdb::write(&path, std::slice::from_ref(&g), o).unwrap();
            let back = nanovdb::read_grid(&path, None).unwrap();
            let ctx = path.display().to_string();
            assert_eq!(back.name, g.name, "{ctx}");
            assert_eq!(back.grid_class, g.grid_class, "{ctx}");
            assert_eq!(back.index_to_world, g.index_to_world, "{ctx}");
            assert_close(&back, &g, o.value, &ctx);
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn invalid_grids_are_errors() {
    let mut g = cloud();
    g.name = "x".repeat(300);
    assert!(writers::nanovdb::to_bytes(&[g], NanoOptions::default()).is_err());
    let mut g = cloud();
    g.index_to_world[1] = [0.0; 4];
    assert!(writers::nanovdb::to_bytes(&[g], NanoOptions::default()).is_err());
}

fn nanovdb_tool(name: &str) -> Option<PathBuf> {
    tool_on_path(
        name,
        "FOGBANK_REQUIRE_NANOVDB",
        "Debian: apt-get install libnanovdb-tools",
    )
}

fn run(tool: &Path, args: &[&std::ffi::OsStr]) -> String {
    let out = Command::new(tool).args(args).output().unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{} {args:?}: {text}", tool.display());
    text
}

#[test]
fn written_nvdb_passes_nanovdb_tools() {
    let (Some(validate), Some(print), Some(convert)) = (
        nanovdb_tool("nanovdb_validate"),
        nanovdb_tool("nanovdb_print"),
        nanovdb_tool("nanovdb_convert"),
    ) else {
        return;
    };
    let dir = temp_dir("fogbank_nvdb_tools");
    for (name, g) in sources() {
        for o in all_options() {
            let path = dir.join(format!("{name}-{:?}-{}.nvdb", o.value, o.codec.name()));
            let ctx = path.display().to_string();
            writers::nanovdb::write(&path, std::slice::from_ref(&g), o).unwrap();
            let v = run(&validate, &["-v".as_ref(), path.as_os_str()]);
            assert!(v.contains("passed") && !v.contains("failed"), "{ctx}: {v}");
            let p = run(&print, &["-l".as_ref(), path.as_os_str()]);
            let count = g.active_voxel_count().to_string();
            let (lo, hi) = g.active_bbox().unwrap();
            let bbox = format!(
                "({},{},{}) -> ({},{},{})",
                lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
            );
            assert!(p.contains(&count), "{ctx}: no voxel count {count} in {p}");
            assert!(p.contains(&bbox), "{ctx}: no box {bbox} in {p}");
            let vdb_path = path.with_extension("vdb");
            run(
                &convert,
                &["-f".as_ref(), path.as_os_str(), vdb_path.as_os_str()],
            );
            let back = vdb::read_grid(&vdb_path, None).unwrap();
            assert_close(&back, &g, o.value, &format!("{ctx} via nanovdb_convert"));
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

/// Uncompressed, the writer's files are byte for byte what `nanovdb_convert`
/// makes of the same grid stored as `.vdb` (node order, statistics,
/// quantisation, map, checksum): the strongest check of the layout.
#[test]
fn uncompressed_nvdb_equals_nanovdb_convert_output() {
    let Some(convert) = nanovdb_tool("nanovdb_convert") else {
        return;
    };
    let dir = temp_dir("fogbank_nvdb_bytes");
    for (name, g) in sources() {
        let vdb_path = dir.join(format!("{name}.vdb"));
        writers::vdb::write(&vdb_path, std::slice::from_ref(&g), Default::default()).unwrap();
        for (value, flag) in [
            (NanoValue::Float, None),
            (NanoValue::Fp8, Some("--fp8")),
            (NanoValue::Fp16, Some("--fp16")),
        ] {
            let reference = dir.join(format!("{name}-{value:?}-ref.nvdb"));
            let mut args: Vec<&std::ffi::OsStr> = vec!["-f".as_ref()];
            args.extend(flag.map(std::ffi::OsStr::new));
            args.extend([vdb_path.as_os_str(), reference.as_os_str()]);
            run(&convert, &args);
            let options = NanoOptions {
                value,
                codec: Codec::None,
            };
            let ours = writers::nanovdb::to_bytes(std::slice::from_ref(&g), options).unwrap();
            let theirs = std::fs::read(&reference).unwrap();
            assert_eq!(ours.len(), theirs.len(), "{name} {value:?}");
            let first = ours.iter().zip(&theirs).position(|(a, b)| a != b);
            assert_eq!(first, None, "{name} {value:?}: first differing byte");
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

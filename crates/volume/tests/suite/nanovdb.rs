//! NanoVDB reader against the OpenVDB reader: committed `.nvdb` fixtures
//! (made by `nanovdb_convert` 32.4 from the committed `.vdb` fixtures of
//! `fixtures/vdb`, see `fixtures/nanovdb/README.md`) must hold the same
//! voxels as their sources; and, when `nanovdb_convert` and `nanovdb_print`
//! are installed, the real files of `data/` and the external data converted
//! at every quantisation and codec, against their `.vdb` voxels and against
//! what `nanovdb_print` reports. Those tests skip with a message without
//! the tools, unless `FOGBANK_REQUIRE_NANOVDB=1` (set by `.ci/run`).

use std::path::{Path, PathBuf};
use std::process::Command;

use fogbank_math::sample_data;
use fogbank_math::testdata::{external_data, tool_on_path};
use fogbank_volume::grid::{BrickGrid, Voxel};
use fogbank_volume::loaders::nanovdb;
use fogbank_volume::loaders::vdb::{self, GridClass, VdbGrid};
use fogbank_volume::loaders::vdb_grid;
use fogbank_volume::VolumeError;
use half::f16;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

/// `nv` holds exactly the voxels, tiles, masks, class and transform of `v`.
fn assert_same_grid(nv: &VdbGrid, v: &VdbGrid, ctx: &str) {
    assert_eq!(nv.name, v.name, "{ctx}");
    assert_eq!(nv.grid_class, v.grid_class, "{ctx}");
    assert_eq!(nv.background, v.background, "{ctx}");
    assert_eq!(nv.index_to_world, v.index_to_world, "{ctx}");
    assert_eq!(nv.tiles, v.tiles, "{ctx}");
    assert_eq!(nv.leaves.len(), v.leaves.len(), "{ctx}");
    assert_eq!(nv.leaves, v.leaves, "{ctx}: leaves (values, masks, order)");
}

/// The brick grid that `read_grid_bricks` streams from `file` holds, bit
/// for bit, what the grid `read_grid` collects becomes through the
/// builder, in `T` (level sets as fog, as the renderer maps them).
fn streamed_equals_collected<T: Voxel>(file: &Path, ctx: &str) {
    let g = nanovdb::read_grid(file, None).unwrap();
    let level_set = vdb_grid::is_level_set(&g);
    let fog = vdb_grid::level_set_fog(g.background);
    let map = move |v: f32| if level_set { fog(v) } else { v.max(0.0) };
    let (builder, want_xf) = vdb_grid::to_builder(g).unwrap();
    let want: BrickGrid<T> = builder.finish_converted(map);
    let (got, xf, outline) = nanovdb::read_grid_bricks::<T, _>(file, None, |_| map).unwrap();
    assert!(outline.leaves.is_empty(), "{ctx}");
    assert_eq!(xf, want_xf, "{ctx}");
    assert!(got.bit_identical(&want), "{ctx}: streamed bricks differ");
}

#[test]
fn streamed_bricks_equal_the_collected_grid() {
    for f in [
        "fog_zip.nvdb",
        "fog_blosc.nvdb",
        "fog_double_zip.nvdb",
        "fog_fp8_zip.nvdb",
        "density_vel_zip.nvdb",
    ] {
        let path = fixture("nanovdb").join(f);
        streamed_equals_collected::<f16>(&path, f);
        streamed_equals_collected::<f32>(&path, f);
    }
}

#[test]
fn committed_fixtures_match_their_openvdb_sources() {
    for (nvdb_file, vdb_file) in [
        ("fog_zip.nvdb", "fog_f32_zip.vdb"),
        ("fog_blosc.nvdb", "fog_f32_zip.vdb"),
        ("density_vel_zip.nvdb", "density_vel.vdb"),
    ] {
        let nv = nanovdb::read_grid(&fixture("nanovdb").join(nvdb_file), None).unwrap();
        let v = vdb::read_grid(&fixture("vdb").join(vdb_file), None).unwrap();
        assert_same_grid(&nv, &v, nvdb_file);
        assert!(nv.active_voxel_count() > 0);
    }
}

#[test]
fn committed_vec3_fixtures_match_their_openvdb_sources() {
    for (nvdb_file, vdb_file, name) in [
        ("vec3_zip.nvdb", "vec3_f32_zip.vdb", None),
        ("density_vel_zip.nvdb", "density_vel.vdb", None),
        ("density_vel_zip.nvdb", "density_vel.vdb", Some("curl")),
    ] {
        let nv = nanovdb::read_vec3_grid(&fixture("nanovdb").join(nvdb_file), name).unwrap();
        let v = vdb::read_vec3_grid(&fixture("vdb").join(vdb_file), name).unwrap();
        for c in 0..3 {
            assert_same_grid(&nv[c], &v[c], &format!("{nvdb_file} / {name:?} / {c}"));
        }
    }
}

/// Double and Vec3d grids (`tools/make_nanovdb_wide_fixtures.py`: the
/// float fixtures widened; the double one then rewritten by NanoVDB) hold
/// the float grids' values exactly, as f32.
#[test]
fn double_fixtures_hold_the_float_values() {
    let dir = fixture("nanovdb");
    let mut d = nanovdb::read_grid(&dir.join("fog_double_zip.nvdb"), None).unwrap();
    let f = nanovdb::read_grid(&dir.join("fog_zip.nvdb"), None).unwrap();
    // OpenVDB's round trip rounds the map (0.1 → 0.1 + 9e-17).
    let rows = d
        .index_to_world
        .iter()
        .flatten()
        .zip(f.index_to_world.iter().flatten());
    assert!(rows.into_iter().all(|(a, b)| (a - b).abs() < 1e-12));
    d.index_to_world = f.index_to_world;
    assert_same_grid(&d, &f, "fog_double_zip.nvdb");
    let list = nanovdb::list_grids(&dir.join("fog_double_zip.nvdb")).unwrap();
    assert_eq!(
        (list[0].value_type.as_str(), list[0].supported),
        ("double", true)
    );
    let d = nanovdb::read_vec3_grid(&dir.join("vec3d_zip.nvdb"), None).unwrap();
    let f = nanovdb::read_vec3_grid(&dir.join("vec3_zip.nvdb"), None).unwrap();
    for c in 0..3 {
        assert_same_grid(&d[c], &f[c], "vec3d_zip.nvdb");
    }
}

#[test]
fn quantised_fixture_is_within_half_a_quantum() {
    let nv = nanovdb::read_grid(&fixture("nanovdb/fog_fp8_zip.nvdb"), None).unwrap();
    let v = vdb::read_grid(&fixture("vdb/fog_f32_zip.vdb"), None).unwrap();
    let e = quantisation_error(&nv, &v, Some(8), "fog_fp8_zip.nvdb");
    assert!(e.beyond_half <= 0.0, "{e:?}");
    assert_eq!(nv.compression, "Fp8 + zip");
}

#[test]
fn grids_are_listed_and_chosen_by_name() {
    let path = fixture("nanovdb/density_vel_zip.nvdb");
    let list = nanovdb::list_grids(&path).unwrap();
    let names: Vec<(&str, &str, bool)> = list
        .iter()
        .map(|d| (d.name.as_str(), d.value_type.as_str(), d.supported))
        .collect();
    assert_eq!(
        names,
        [
            ("curl", "Vec3f", false),
            ("density", "float", true),
            ("vel", "Vec3f", false)
        ]
    );
    assert_eq!(list[1].grid_class, GridClass::FogVolume);
    assert_eq!(list[2].grid_class, GridClass::Staggered);
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(nanovdb::list_grids_from_bytes(&path, &bytes).unwrap(), list);
    let named = nanovdb::read_grid(&path, Some("density")).unwrap();
    assert_eq!(
        named,
        nanovdb::read_grid_from_bytes(&path, &bytes, None).unwrap()
    );
    let vel = nanovdb::read_vec3_grid_from_bytes(&path, &bytes, Some("vel")).unwrap();
    assert_eq!(vel[1].name, "vel.y");
    let wrong = nanovdb::read_grid(&path, Some("vel"))
        .unwrap_err()
        .to_string();
    assert!(wrong.contains("read_vec3_grid"), "{wrong}");
    let wrong = nanovdb::read_vec3_grid(&path, Some("density"))
        .unwrap_err()
        .to_string();
    assert!(wrong.contains("read_grid"), "{wrong}");
    let missing = nanovdb::read_grid(&path, Some("smoke")).unwrap_err();
    assert!(
        matches!(&missing, VolumeError::GridNotFound { available, .. } if available.len() == 3),
        "{missing}"
    );
}

/// Largest deviation of a quantised grid `nv` from its source `v`, in
/// value units and in quanta of each leaf (`bits` wide; `None` for FpN,
/// whose width varies by leaf and is not compared in quanta).
#[derive(Debug, Default, Clone, Copy)]
struct QuantError {
    absolute: f32,
    in_quanta: f32,
    /// Largest excess over half a quantum plus the f32 rounding of
    /// `code · quantum + minimum` (a few ulps of the leaf's largest value).
    beyond_half: f32,
}

fn quantisation_error(nv: &VdbGrid, v: &VdbGrid, bits: Option<u32>, ctx: &str) -> QuantError {
    assert_eq!(nv.background, v.background, "{ctx}");
    assert_eq!(
        nv.tiles, v.tiles,
        "{ctx}: tiles are stored in full precision"
    );
    assert_eq!(nv.leaves.len(), v.leaves.len(), "{ctx}");
    let mut e = QuantError::default();
    for (a, b) in nv.leaves.iter().zip(&v.leaves) {
        assert_eq!((a.origin, a.active), (b.origin, b.active), "{ctx}");
        // NanoVDB quantises between the minimum and maximum of all 512
        // values, active or not.
        let (lo, hi) = b
            .values
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        let quantum = bits.map(|n| (hi - lo) / ((1u32 << n) - 1) as f32);
        let rounding = 4.0 * f32::EPSILON * lo.abs().max(hi.abs());
        for (x, y) in a.values.iter().zip(b.values.iter()) {
            let d = (x - y).abs();
            e.absolute = e.absolute.max(d);
            if let Some(q) = quantum.filter(|&q| q > 0.0) {
                e.in_quanta = e.in_quanta.max(d / q);
                e.beyond_half = e.beyond_half.max(d - 0.5 * q - rounding);
            }
        }
    }
    e
}

/// The NanoVDB command-line tool `name`, or `None` (after saying so) when
/// it is not installed; a failure instead when `FOGBANK_REQUIRE_NANOVDB=1`.
fn nanovdb_tool(name: &str) -> Option<PathBuf> {
    tool_on_path(
        name,
        "FOGBANK_REQUIRE_NANOVDB",
        "Debian: apt-get install libnanovdb-tools",
    )
}

/// The real OpenVDB files: committed dragon and sphere, external cube.
fn real_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = ["dragon.vdb", "sphere.vdb"]
        .iter()
        .map(|n| sample_data::committed(n))
        .collect();
    files.extend(external_data("cube.vdb"));
    files
}

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fogbank-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn convert(tool: &Path, args: &[&str], vdb: &Path, out: &Path) {
    let status = Command::new(tool)
        .args(["-f"])
        .args(args)
        .arg(vdb)
        .arg(out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "nanovdb_convert {args:?} {}: {}",
        vdb.display(),
        String::from_utf8_lossy(&status.stderr)
    );
}

/// Active voxel count and inclusive index bbox of each grid, from the
/// table `nanovdb_print -l` prints (columns separated by two or more
/// spaces; the bbox as `(x,y,z) -> (x,y,z)`).
fn printed_grids(tool: &Path, file: &Path) -> Vec<(String, u64, [i32; 6])> {
    let out = Command::new(tool).arg("-l").arg(file).output().unwrap();
    assert!(out.status.success(), "nanovdb_print {}", file.display());
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let split = |l: &str| -> Vec<String> {
        l.split("  ")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(str::to_string)
            .collect()
    };
    let mut lines = text.lines().skip_while(|l| !l.starts_with("#  Name"));
    let header = split(lines.next().expect("nanovdb_print table header"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (name, voxels, bbox) = (col("Name"), col("# Voxels"), col("Index Bounding Box"));
    lines
        .take_while(|l| !l.trim().is_empty())
        .map(|l| {
            let cells = split(l);
            let nums: Vec<i32> = cells[bbox]
                .split(|c: char| !(c.is_ascii_digit() || c == '-'))
                .filter(|s| !s.is_empty() && *s != "-")
                .map(|s| s.parse().unwrap())
                .collect();
            (
                cells[name].clone(),
                cells[voxels].parse().unwrap(),
                std::array::from_fn(|i| nums[i]),
            )
        })
        .collect()
}

const QUANTISATIONS: [(&str, Option<u32>); 5] = [
    ("", None),
    ("--fp4", Some(4)),
    ("--fp8", Some(8)),
    ("--fp16", Some(16)),
    ("--fpN", None),
];
const CODECS: [&str; 3] = ["", "-z", "-b"];

/// Every real file at every quantisation and codec: float grids hold the
/// `.vdb` voxels exactly, Fp4/8/16 within half a quantum of each leaf, FpN
/// within the converter's default tolerance (0.01 for fog volumes, a tenth
/// of a voxel for level sets); voxel counts and index boxes agree with
/// `nanovdb_print`.
#[test]
fn converted_real_files_match_openvdb_and_nanovdb_print() {
    let (Some(convert_tool), Some(print_tool)) = (
        nanovdb_tool("nanovdb_convert"),
        nanovdb_tool("nanovdb_print"),
    ) else {
        return;
    };
    let dir = temp_dir("nanovdb-convert");
    for vdb_path in real_files() {
        let v = vdb::read_grid(&vdb_path, None).unwrap();
        let stem = vdb_path.file_stem().unwrap().to_string_lossy().to_string();
        for (quant, bits) in QUANTISATIONS {
            for codec in CODECS {
                let out = dir.join(format!("{stem}{quant}{codec}.nvdb"));
                let args: Vec<&str> = [quant, codec]
                    .into_iter()
                    .filter(|a| !a.is_empty())
                    .collect();
                convert(&convert_tool, &args, &vdb_path, &out);
                let nv = nanovdb::read_grid(&out, None).unwrap();
                let ctx = format!("{stem} {args:?}");
                check_against_print(&nv, &printed_grids(&print_tool, &out), &ctx);
                streamed_equals_collected::<f16>(&out, &ctx);
                if codec.is_empty() {
                    same_as_nanovdb_values(&convert_tool, &nv, &out, &ctx);
                }
                match quant {
                    "" => {
                        let (lo, hi) = nv.active_bbox().unwrap();
                        eprintln!(
                            "{ctx}: {} leaves, {} active voxels, index bbox {lo:?} – {hi:?}",
                            nv.leaves.len(),
                            nv.active_voxel_count()
                        );
                        assert_same_grid(&nv, &v, &ctx)
                    }
                    _ => {
                        let e = quantisation_error(&nv, &v, bits, &ctx);
                        let tolerance = match v.grid_class {
                            GridClass::LevelSet => 0.1 * v.index_to_world[0][0] as f32,
                            _ => 0.01,
                        };
                        eprintln!(
                            "{ctx}: {} leaves, max error {:.3e} ({:.4} quanta)",
                            nv.leaves.len(),
                            e.absolute,
                            e.in_quanta
                        );
                        assert!(e.beyond_half <= 0.0, "{ctx}: {e:?}");
                        if bits.is_none() {
                            assert!(e.absolute <= tolerance * 1.001, "{ctx}: {e:?}");
                        }
                    }
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `nv`, read from `file`, holds bit for bit the values NanoVDB itself
/// decodes: `nanovdb_convert` turns `file` back into an OpenVDB file
/// (dequantising through NanoVDB's own `getValue`), which the OpenVDB
/// reader reads.
fn same_as_nanovdb_values(tool: &Path, nv: &VdbGrid, file: &Path, ctx: &str) {
    let back = file.with_extension("back.vdb");
    convert(tool, &[], file, &back);
    let v = vdb::read_grid(&back, Some(&nv.name)).unwrap();
    assert_eq!(nv.tiles, v.tiles, "{ctx}: round trip");
    assert_eq!(nv.leaves.len(), v.leaves.len(), "{ctx}: round trip");
    for (a, b) in nv.leaves.iter().zip(&v.leaves) {
        assert_eq!(a.origin, b.origin, "{ctx}: round trip");
        let bits = |l: &vdb::VdbLeaf| l.values.map(f32::to_bits);
        assert!(
            bits(a) == bits(b),
            "{ctx}: leaf {:?} differs from NanoVDB's values",
            a.origin
        );
    }
    let _ = std::fs::remove_file(back);
}

fn check_against_print(nv: &VdbGrid, printed: &[(String, u64, [i32; 6])], ctx: &str) {
    let (_, voxels, bbox) = printed
        .iter()
        .find(|(n, ..)| *n == nv.name)
        .unwrap_or_else(|| panic!("{ctx}: nanovdb_print lists no `{}`", nv.name));
    assert_eq!(nv.active_voxel_count(), *voxels, "{ctx}: active voxels");
    let (lo, hi) = nv.active_bbox().unwrap();
    assert_eq!([lo, hi].concat(), bbox.to_vec(), "{ctx}: index bbox");
}

/// Full checksums (`-c full`), checked for every node, and no checksum at
/// all (`-c none`), both read.
#[test]
fn checksum_modes_of_the_converter_are_read() {
    let Some(convert_tool) = nanovdb_tool("nanovdb_convert") else {
        return;
    };
    let dir = temp_dir("nanovdb-checksum");
    let dragon = sample_data::committed("dragon.vdb");
    let v = vdb::read_grid(&dragon, None).unwrap();
    for quant in ["", "--fp4", "--fpN"] {
        for mode in ["full", "none", "partial"] {
            let out = dir.join(format!("dragon{quant}-{mode}.nvdb"));
            let args: Vec<&str> = [quant, "-c", mode]
                .into_iter()
                .filter(|a| !a.is_empty())
                .collect();
            convert(&convert_tool, &args, &dragon, &out);
            let nv = nanovdb::read_grid(&out, None).unwrap();
            if quant.is_empty() {
                assert_same_grid(&nv, &v, mode);
            }
            // A changed voxel value: caught by the full checksum (which
            // covers every leaf; FpN leaves only by their header), missed
            // by the partial one (head and root only).
            let mut bytes = std::fs::read(&out).unwrap();
            let n = bytes.len();
            bytes[n - 1] ^= 0x40;
            let read = nanovdb::read_grid_from_bytes(&out, &bytes, None);
            match (mode, quant) {
                ("full", "" | "--fp4") => {
                    let e = read.unwrap_err().to_string();
                    assert!(e.contains("checksum mismatch"), "{mode} {quant}: {e}");
                }
                _ => assert!(read.is_ok(), "{mode} {quant}"),
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

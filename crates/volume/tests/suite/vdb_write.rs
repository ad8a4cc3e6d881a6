//! The OpenVDB writer against the reader and against OpenVDB itself: every
//! grid written (float and half, each codec, with and without active-mask
//! compression) reads back voxel for voxel in
//! fogbank's reader, and, when Debian's `python3-openvdb` is installed,
//! `pyopenvdb` reads the same active voxel count, value sum, voxels and
//! transform. The OpenVDB checks skip with a message without the binding,
//! unless `FOGBANK_REQUIRE_OPENVDB=1` (set by `.ci/run`).

use std::path::{Path, PathBuf};
use std::process::Command;

use fogbank_math::sample_data;
use fogbank_math::testdata::python_with_module;
use fogbank_math::DAffine3;
use fogbank_volume::loaders::vdb::{self, VdbGrid, VdbLeaf};
use fogbank_volume::procedural::cloud_grid;
use fogbank_volume::writers::{self, Codec, VdbOptions};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/vdb")
        .join(name)
}

/// A procedural cloud as the exporter hands it over, with an affine map.
fn cloud() -> VdbGrid {
    let g = cloud_grid::<f32>(40, 7).unwrap();
    let xf = DAffine3::from_cols_array(&[
        0.02, 0.01, 0.0, 0.0, 0.03, 0.0, 0.0, 0.0, 0.025, 1.0, -2.0, 0.5,
    ]);
    writers::from_brick_grid(&g, xf, "density", 0.0)
}

/// Source grids: a procedural cloud, the dragon, a grid with tiles at
/// every level.
fn sources() -> Vec<(String, VdbGrid)> {
    vec![
        ("cloud".into(), cloud()),
        (
            "dragon".into(),
            vdb::read_grid(&sample_data::committed("dragon.vdb"), None).unwrap(),
        ),
        (
            "tiles".into(),
            vdb::read_grid(&fixture("tiles_f32_zip.vdb"), None).unwrap(),
        ),
    ]
}

fn all_options() -> Vec<VdbOptions> {
    let mut out = Vec::new();
    for half in [false, true] {
        for codec in [Codec::None, Codec::Zip, Codec::Blosc] {
            for active_mask in [false, true] {
                out.push(VdbOptions {
                    half,
                    codec,
                    active_mask,
                });
            }
        }
    }
    out
}

/// `g` as a half grid stores it: node values rounded to half precision,
/// background and tiles full width.
fn rounded(g: &VdbGrid, half: bool) -> VdbGrid {
    let mut g = g.clone();
    if half {
        for leaf in &mut g.leaves {
            for v in leaf.values.iter_mut() {
                *v = half::f16::from_f32(*v).to_f32();
            }
        }
        for t in g.tiles.iter_mut().filter(|t| t.size < 4096) {
            t.value = half::f16::from_f32(t.value).to_f32();
        }
    }
    g
}

/// Same tiles and leaves (values and masks), in any order; a mismatch is
/// reported by origin, not by printing the grids.
fn assert_same_voxels(a: &VdbGrid, b: &VdbGrid, ctx: &str) {
    type Tiles = Vec<([i32; 3], u32, u32, bool)>;
    fn sorted(g: &VdbGrid) -> (Vec<&VdbLeaf>, Tiles) {
        let mut l: Vec<_> = g.leaves.iter().collect();
        l.sort_by_key(|l| l.origin);
        let mut t: Vec<_> = g
            .tiles
            .iter()
            .map(|t| (t.origin, t.size, t.value.to_bits(), t.active))
            .collect();
        t.sort_unstable();
        (l, t)
    }
    let ((la, ta), (lb, tb)) = (sorted(a), sorted(b));
    assert_eq!(ta, tb, "{ctx}: tiles");
    assert_eq!(la.len(), lb.len(), "{ctx}: leaf count");
    for (x, y) in la.iter().zip(&lb) {
        assert!(
            x == y,
            "{ctx}: leaf at {:?} differs from the leaf at {:?}",
            x.origin,
            y.origin
        );
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `g` written with `o` into `dir`, under a name that says how.
fn written(dir: &Path, name: &str, g: &VdbGrid, o: VdbOptions) -> PathBuf {
    let (half, codec, mask) = (o.half, o.codec.name(), o.active_mask);
    let path = dir.join(format!("{name}-{half}-{codec}-{mask}.vdb"));
    writers::vdb::write(&path, std::slice::from_ref(g), o).unwrap();
    path
}

#[test]
fn written_vdb_reads_back_voxel_for_voxel() {
    let dir = temp_dir("fogbank_vdb_write");
    for (name, g) in sources() {
        for o in all_options() {
            let path = written(&dir, &name, &g, o);
            let back = vdb::read_grid(&path, None).unwrap();
            let want = rounded(&g, o.half);
            let ctx = path.display().to_string();
            assert_eq!(back.name, g.name, "{ctx}");
            assert_eq!(back.grid_class, g.grid_class, "{ctx}");
            assert_eq!(back.stored_as_half, o.half, "{ctx}");
            assert_eq!(back.background, want.background, "{ctx}");
            assert_eq!(back.index_to_world, g.index_to_world, "{ctx}");
            assert_same_voxels(&back, &want, &ctx);
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn several_grids_and_duplicate_names() {
    let g = cloud();
    let mut other = g.clone();
    other.name = "temperature".into();
    let bytes =
        writers::vdb::to_bytes(&[g.clone(), other, g.clone()], VdbOptions::default()).unwrap();
    let path = Path::new("mem.vdb");
    let names: Vec<_> = vdb::list_grids_from_bytes(path, &bytes)
        .unwrap()
        .into_iter()
        .map(|d| d.name)
        .collect();
    assert_eq!(names, ["density[0]", "temperature", "density[1]"]);
    let back = vdb::parse_grid(path, &bytes, Some("density[1]")).unwrap();
    assert_same_voxels(&back, &g, "density[1]");
}

#[test]
fn invalid_grids_are_errors() {
    let mut g = cloud();
    g.index_to_world[0][0] = 0.0;
    g.index_to_world[1][0] = 0.0;
    g.index_to_world[2][0] = 0.0;
    assert!(writers::vdb::to_bytes(&[g], VdbOptions::default()).is_err());
    let mut g = cloud();
    g.leaves[0].origin[0] += 1;
    assert!(writers::vdb::to_bytes(&[g], VdbOptions::default()).is_err());
    let mut g = cloud();
    g.name = "a\x1eb".into();
    assert!(writers::vdb::to_bytes(&[g], VdbOptions::default()).is_err());
}

/// What pyopenvdb reads from `path`: name, class, active voxel count, sum
/// of active values, values at `probes`, and the world position of voxel
/// (1, 2, 3).
const PY: &str = r#"
import sys, pyopenvdb as vdb
g = vdb.readAll(sys.argv[1])[0][0]
s = 0.0
for it in g.citerOnValues():
    s += it.value * it.count
a = g.getConstAccessor()
print(g.name)
print(g.gridClass)
print(g.activeVoxelCount())
print(repr(s))
for p in sys.argv[2:]:
    print(repr(a.getValue(tuple(int(v) for v in p.split(',')))))
print(' '.join(repr(v) for v in g.transform.indexToWorld((1, 2, 3))))
"#;

#[test]
fn written_vdb_reads_in_openvdb() {
    let Some(py) = python_with_module(
        "pyopenvdb",
        "FOGBANK_REQUIRE_OPENVDB",
        "Debian: apt-get install python3-openvdb",
    ) else {
        return;
    };
    let dir = temp_dir("fogbank_vdb_openvdb");
    for (name, g) in sources() {
        for o in all_options() {
            let path = written(&dir, &name, &g, o);
            check_with_openvdb(&py, &path, &rounded(&g, o.half));
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

fn check_with_openvdb(py: &Path, path: &Path, g: &VdbGrid) {
    let ctx = path.display().to_string();
    // Probes: active voxels of the first and last leaves, a tile, outside.
    let mut probes = vec![[-100_000, 3, 5]];
    for leaf in [g.leaves.first(), g.leaves.last()].into_iter().flatten() {
        probes.push(leaf.origin);
        probes.push(leaf.origin.map(|v| v + 5));
    }
    probes.extend(g.tiles.iter().map(|t| t.origin.map(|v| v + 1)));
    let out = Command::new(py)
        .args(["-c", PY])
        .arg(path)
        .args(probes.iter().map(|p| format!("{},{},{}", p[0], p[1], p[2])))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{ctx}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], g.name, "{ctx}");
    assert_eq!(lines[1], "fog volume", "{ctx}");
    assert_eq!(
        lines[2].parse::<u64>().unwrap(),
        g.active_voxel_count(),
        "{ctx}"
    );
    let sum: f64 = lines[3].parse().unwrap();
    let want = g.active_value_sum();
    assert!(
        (sum - want).abs() <= 1e-9 * want.abs().max(1.0),
        "{ctx}: sum {sum} vs {want}"
    );
    for (p, line) in probes.iter().zip(&lines[4..]) {
        let v: f64 = line.parse().unwrap();
        assert_eq!(v as f32, g.value_at(*p), "{ctx}: voxel {p:?}");
    }
    let world: Vec<f64> = lines[4 + probes.len()]
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    let m = g.index_to_world;
    for r in 0..3 {
        let want = m[r][0] + 2.0 * m[r][1] + 3.0 * m[r][2] + m[r][3];
        assert!((world[r] - want).abs() < 1e-12, "{ctx}: world {world:?}");
    }
}

//! OpenVDB reader against reference values written by OpenVDB itself
//! (`tools/make_vdb_fixtures.py` → `fixtures/vdb/manifest.json`) and against
//! real-world files: the committed ones of `data/` and the external ones
//! (`tools/fetch_data.sh` or `../shared/data`), which skip when missing.

use std::path::{Path, PathBuf};

use fogbank_math::sample_data;
use fogbank_math::testdata::external_data;
use fogbank_volume::loaders::vdb::{self, GridClass, VdbGrid};
use fogbank_volume::VolumeError;
use serde_json::Value;

fn fixture_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/vdb")
}

/// A fixture's bytes; `*.vdb.gz` fixtures (the uncompressed vec3 files,
/// large but mostly background) are gunzipped.
fn fixture_bytes(file: &str) -> Vec<u8> {
    let raw = std::fs::read(fixture_dir().join(file)).unwrap();
    if !file.ends_with(".gz") {
        return raw;
    }
    let mut out = Vec::new();
    std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&raw[..]), &mut out).unwrap();
    out
}

/// A path to read `file` from: the fixture itself, or its gunzipped copy in
/// a temporary directory.
fn fixture_path(file: &str) -> PathBuf {
    let Some(plain) = file.strip_suffix(".gz") else {
        return fixture_dir().join(file);
    };
    let dir = std::env::temp_dir().join("fogbank-vdb-read");
    std::fs::create_dir_all(&dir).unwrap();
    // Written aside and renamed, so that concurrent test runs never see a
    // partial file.
    let path = dir.join(plain);
    let tmp = dir.join(format!("{plain}.{}", std::process::id()));
    std::fs::write(&tmp, fixture_bytes(file)).unwrap();
    std::fs::rename(&tmp, &path).unwrap();
    path
}

fn manifest() -> Value {
    let text = std::fs::read_to_string(fixture_dir().join("manifest.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn coord(v: &Value) -> [i32; 3] {
    [0, 1, 2].map(|c| v[c].as_i64().unwrap() as i32)
}

/// Compares one grid with the values OpenVDB reported for it.
fn check_grid(file: &str, grid: &VdbGrid, r: &Value) {
    let ctx = format!("{file} / {}", r["name"]);
    assert_eq!(grid.name, r["name"].as_str().unwrap(), "{ctx}");
    assert_eq!(
        grid.grid_class.name(),
        r["grid_class"].as_str().unwrap(),
        "{ctx}"
    );
    assert_eq!(
        grid.stored_as_half,
        r["stored_as_half"].as_bool().unwrap(),
        "{ctx}"
    );
    assert_eq!(
        grid.compression,
        r["compression"].as_str().unwrap(),
        "{ctx}"
    );
    assert_eq!(grid.background as f64, f(&r["background"]), "{ctx}");
    assert_eq!(
        grid.active_voxel_count(),
        r["active_voxel_count"].as_u64().unwrap(),
        "{ctx}"
    );
    match grid.active_bbox() {
        Some((lo, hi)) => {
            assert_eq!(lo, coord(&r["bbox"][0]), "{ctx}: bbox min");
            assert_eq!(hi, coord(&r["bbox"][1]), "{ctx}: bbox max");
        }
        None => assert!(r["bbox"].is_null(), "{ctx}: no active voxels"),
    }
    match grid.active_value_range() {
        Some((lo, hi)) => {
            assert_eq!(lo as f64, f(&r["range"][0]), "{ctx}: min");
            assert_eq!(hi as f64, f(&r["range"][1]), "{ctx}: max");
        }
        None => assert!(r["range"].is_null(), "{ctx}"),
    }
    let sum = f(&r["sum"]);
    let got = grid.active_value_sum();
    assert!(
        (got - sum).abs() <= 1e-9 * sum.abs().max(1.0),
        "{ctx}: sum {got} vs {sum}"
    );
    for row in 0..4 {
        for col in 0..4 {
            let want = f(&r["transform"][row][col]);
            let have = grid.index_to_world[row][col];
            assert!(
                (have - want).abs() < 1e-12,
                "{ctx}: transform[{row}][{col}] {have} vs {want}"
            );
        }
    }
    let samples = r["samples"].as_array().unwrap();
    assert!(samples.len() >= 30, "{ctx}: manifest has too few samples");
    for s in samples {
        let ijk = [0, 1, 2].map(|c| s[c].as_i64().unwrap() as i32);
        let want = f(&s[3]) as f32;
        assert_eq!(grid.value_at(ijk), want, "{ctx}: value at {ijk:?}");
    }
}

/// Checks every read listed for one manifest entry against the file at `path`.
fn check_entry(entry: &Value, path: &Path) {
    let file = entry["file"].as_str().unwrap();
    let listed = vdb::list_grids(path).unwrap();
    let want = entry["grids"].as_array().unwrap();
    assert_eq!(listed.len(), want.len(), "{file}: grid count");
    let mut names: Vec<(String, String, &str)> = listed
        .iter()
        .map(|d| {
            let plain = d.name.split('[').next().unwrap().to_string();
            (plain, d.value_type.clone(), d.grid_class.name())
        })
        .collect();
    let mut expected: Vec<(String, String, &str)> = want
        .iter()
        .map(|g| {
            (
                g["name"].as_str().unwrap().to_string(),
                g["value_type"].as_str().unwrap().to_string(),
                g["grid_class"].as_str().unwrap(),
            )
        })
        .collect();
    names.sort();
    expected.sort();
    assert_eq!(names, expected, "{file}: grid list");
    for d in &listed {
        assert_eq!(d.supported, d.value_type == "float", "{file}: {}", d.name);
    }
    for r in entry["reads"].as_array().unwrap() {
        let grid = vdb::read_grid(path, r["request"].as_str()).unwrap();
        assert_eq!(
            grid.file_version as u64,
            entry["file_version"].as_u64().unwrap(),
            "{file}"
        );
        check_grid(file, &grid, r);
    }
    let Some(reads) = entry["vec3_reads"].as_array() else {
        return;
    };
    let bytes = std::fs::read(path).unwrap();
    for r in reads {
        let request = r["request"].as_str();
        let grids = vdb::read_vec3_grid(path, request).unwrap();
        let ctx = format!("{file} / {request:?}");
        for (c, g) in grids.iter().enumerate() {
            assert_eq!(
                g.file_version as u64,
                entry["file_version"].as_u64().unwrap(),
                "{ctx}"
            );
            check_grid(file, g, &r["components"][c]);
        }
        assert_same_topology(&grids, &ctx);
        assert_eq!(
            vdb::parse_vec3_grid(path, &bytes, request).unwrap(),
            grids,
            "{ctx}: bytes vs file"
        );
    }
}

/// The three components of a vec3 grid share every structural field.
fn assert_same_topology(g: &[VdbGrid; 3], ctx: &str) {
    let shape = |g: &VdbGrid| {
        let leaves: Vec<_> = g.leaves.iter().map(|l| (l.origin, l.active)).collect();
        let tiles: Vec<_> = g
            .tiles
            .iter()
            .map(|t| (t.origin, t.size, t.active))
            .collect();
        let head = (g.grid_class, g.stored_as_half, g.compression.clone());
        (head, g.index_to_world, leaves, tiles)
    };
    assert!(shape(&g[1]) == shape(&g[0]), "{ctx}: y differs from x");
    assert!(shape(&g[2]) == shape(&g[0]), "{ctx}: z differs from x");
    let base = g[0].name.strip_suffix(".x").expect("component name");
    let names = g.each_ref().map(|c| c.name.as_str());
    assert_eq!(
        names,
        ["x", "y", "z"].map(|a| format!("{base}.{a}")),
        "{ctx}"
    );
}

/// Asserts that `err` (an error's message) contains every one of `parts`.
fn assert_mentions(err: impl std::fmt::Display, parts: &[&str]) {
    let err = err.to_string();
    let missing: Vec<_> = parts.iter().filter(|p| !err.contains(*p)).collect();
    assert!(missing.is_empty(), "{err}\nlacks {missing:?}");
}

fn entry(file: &str) -> Value {
    manifest()["fixtures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["file"] == file)
        .unwrap_or_else(|| panic!("{file} not in manifest"))
        .clone()
}

#[test]
fn fixtures_match_openvdb_reference() {
    let m = manifest();
    let mut checked = 0;
    for e in m["fixtures"].as_array().unwrap() {
        let file = e["file"].as_str().unwrap();
        // The real files have tests of their own.
        if file.starts_with("shared:") || file.starts_with("data:") {
            continue;
        }
        check_entry(e, &fixture_path(file));
        checked += 1;
    }
    assert!(checked >= 24, "only {checked} fixtures in manifest");
    let vec3 = m["fixtures"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["vec3_reads"].is_array())
        .count();
    assert!(vec3 >= 11, "only {vec3} vec3 fixtures in manifest");
}

#[test]
fn float_and_half_in_every_compression() {
    for prec in ["f32", "half"] {
        for codec in ["none", "active", "zip", "blosc"] {
            let name = format!("fog_{prec}_{codec}.vdb");
            let g = vdb::read_grid(&fixture_dir().join(&name), None).unwrap();
            assert_eq!(g.stored_as_half, prec == "half", "{name}");
            let want = match codec {
                "none" => "none",
                "active" => "active-mask",
                "zip" => "zip + active-mask",
                _ => "blosc + active-mask",
            };
            assert_eq!(g.compression, want, "{name}");
        }
    }
    // Same data regardless of compression.
    let a = vdb::read_grid(&fixture_dir().join("fog_f32_none.vdb"), None).unwrap();
    for codec in ["active", "zip", "blosc"] {
        let b = vdb::read_grid(&fixture_dir().join(format!("fog_f32_{codec}.vdb")), None).unwrap();
        assert_eq!(a.leaves, b.leaves, "{codec}");
        assert_eq!(a.tiles, b.tiles, "{codec}");
    }
}

fn vec3_fixture(prec: &str, codec: &str) -> [VdbGrid; 3] {
    let file = match codec {
        "none" => format!("vec3_{prec}_none.vdb.gz"),
        _ => format!("vec3_{prec}_{codec}.vdb"),
    };
    let path = fixture_dir().join(&file);
    vdb::parse_vec3_grid(&path, &fixture_bytes(&file), None).unwrap()
}

#[test]
fn vec3_in_every_precision_and_compression() {
    let h = |v: f32| half::f16::from_f32(v).to_f32();
    let mut by_prec = Vec::new();
    for prec in ["f32", "half"] {
        let mut first: Option<[VdbGrid; 3]> = None;
        for codec in ["none", "active", "zip", "blosc"] {
            let g = vec3_fixture(prec, codec);
            let ctx = format!("{prec} {codec}");
            assert_eq!(g[0].name, "vel.x", "{ctx}");
            assert_eq!(g[0].stored_as_half, prec == "half", "{ctx}");
            let want = match codec {
                "none" => "none",
                "active" => "active-mask",
                "zip" => "zip + active-mask",
                _ => "blosc + active-mask",
            };
            assert_eq!(g[2].compression, want, "{ctx}");
            // The writer rounds the background to half but stores it in
            // full width; root tiles it neither rounds nor narrows; the 32³
            // node's 128³ tile is stored as half.
            let round = |v: [f32; 3]| v.map(|v| if prec == "half" { h(v) } else { v });
            let at = |ijk| g.each_ref().map(|c| c.value_at(ijk));
            let bg = g.each_ref().map(|c| c.background);
            assert_eq!(bg, round([0.1, -0.2, 0.3]), "{ctx}");
            let root = [at([-5, -6, -7]), at([5000, 1, 2])];
            assert_eq!(root, [[0.7, -0.1, 0.2], [-0.3, 0.6, 0.9]], "{ctx}");
            assert_eq!(at([200, 5, 5]), round([0.1, 0.2, -0.3]), "{ctx}: 128³ tile");
            // Swirl at (20, 17, 10), c = 16; an inactive -background voxel.
            assert_eq!(at([20, 17, 10]), round([0.3, 0.31, 0.2]), "{ctx}");
            assert_eq!(at([72, 0, 1]), bg.map(|v| -v), "{ctx}");
            // Same data regardless of compression.
            let first = first.get_or_insert_with(|| g.clone());
            for c in 0..3 {
                assert!(first[c].leaves == g[c].leaves, "{ctx}: leaves of {c}");
                assert!(first[c].tiles == g[c].tiles, "{ctx}: tiles of {c}");
            }
        }
        by_prec.push(first.unwrap());
    }
    // Half within half precision (2^-11 relative) of full.
    let (full, half) = (&by_prec[0], &by_prec[1]);
    for c in 0..3 {
        assert_eq!(full[c].leaves.len(), half[c].leaves.len());
        for (a, b) in full[c].leaves.iter().zip(&half[c].leaves) {
            assert_eq!((a.origin, a.active), (b.origin, b.active));
            for (x, y) in a.values.iter().zip(b.values.iter()) {
                assert!((x - y).abs() <= x.abs() / 2048.0, "{x} vs {y}");
            }
        }
    }
}

#[test]
fn vec3_default_grid_selection() {
    // `vel` is chosen by name although `curl` comes first; `read_grid`
    // still picks `density`. (Values, also of the instance and the stream
    // fixtures, are checked against the manifest.)
    let dv = fixture_dir().join("density_vel.vdb");
    let listed = vdb::list_grids(&dv).unwrap();
    let first_vec3 = listed.iter().find(|d| d.value_type == "vec3s").unwrap();
    assert_eq!(first_vec3.name, "curl", "{listed:?}");
    let vel = vdb::read_vec3_grid(&dv, None).unwrap();
    assert_eq!(vel[0].name, "vel.x");
    assert_eq!(vel[0].grid_class, GridClass::Staggered);
    assert!(vel[0].stored_as_half);
    assert_eq!(vdb::read_grid(&dv, None).unwrap().name, "density");
    assert!(!vdb::read_vec3_grid(&dv, Some("curl")).unwrap()[0].stored_as_half);
    // No `vel`, `v` or `velocity`: the first vec3s grid.
    let flow = vdb::read_vec3_grid(&fixture_dir().join("vec3_instance.vdb"), None).unwrap();
    assert_eq!(flow[1].name, "flow.y");
    let stream = vdb::read_vec3_grid(&fixture_dir().join("vec3_stream.vdb"), None).unwrap();
    assert_eq!(stream[2].name, "vel.z");
    // The single-voxel vec3s grid of multi.vdb.
    let m = vdb::read_vec3_grid(&fixture_dir().join("multi.vdb"), None).unwrap();
    assert_eq!(m.each_ref().map(|g| g.value_at([1, 2, 3])), [1.0, 2.0, 3.0]);
    assert_eq!(m.each_ref().map(|g| g.active_voxel_count()), [1; 3]);
    // No vec3s grid at all: the error lists what there is.
    let err = vdb::read_vec3_grid(&fixture_dir().join("fog_f32_zip.vdb"), None).unwrap_err();
    assert_mentions(err, &["fog_f32_zip.vdb", "no vec3s", "`density` (float)"]);
}

#[test]
fn vec3_wrong_type_errors_name_grid_and_type() {
    let dv = fixture_dir().join("density_vel.vdb");
    let err = vdb::read_vec3_grid(&dv, Some("density")).unwrap_err();
    assert!(matches!(err, VolumeError::Format { .. }), "{err:?}");
    assert_mentions(
        err,
        &["density_vel.vdb", "`density`", "`float`", "must be vec3s"],
    );
    let err = vdb::read_grid(&dv, Some("vel")).unwrap_err();
    let parts = [
        "density_vel.vdb",
        "`vel`",
        "`vec3s`",
        "stored as half",
        "read_vec3_grid",
    ];
    assert_mentions(err, &parts);
    let err = vdb::read_vec3_grid(&dv, Some("smoke")).unwrap_err();
    assert!(matches!(err, VolumeError::GridNotFound { .. }), "{err:?}");

    // vec3d and vec3i trees: the same file with the tree type renamed.
    let path = fixture_dir().join("vec3_f32_zip.vdb");
    let bytes = std::fs::read(&path).unwrap();
    let from = b"Tree_vec3s_5_4_3";
    let at = bytes.windows(from.len()).position(|w| w == from).unwrap();
    for ty in ["vec3d", "vec3i"] {
        let mut patched = bytes.clone();
        patched[at + 5..at + 10].copy_from_slice(ty.as_bytes());
        let err = vdb::parse_vec3_grid(&path, &patched, Some("vel")).unwrap_err();
        let quoted = format!("`{ty}`");
        let must = "must be vec3s (Tree_vec3s_5_4_3, float or half";
        assert_mentions(err, &["vec3_f32_zip.vdb", "`vel`", &quoted, must]);
        let err = vdb::parse_vec3_grid(&path, &patched, None).unwrap_err();
        assert_mentions(err, &[&format!("`vel` ({ty})")]);
        assert!(vdb::parse_grid(&path, &patched, Some("vel")).is_err());
    }
}

#[test]
fn dragon_matches_vdb_print() {
    let path = sample_data::committed("dragon.vdb");
    check_entry(&entry("data:dragon.vdb"), &path);
    let g = vdb::read_grid(&path, Some("density")).unwrap();
    assert_eq!(g.file_version, 224);
    assert_eq!(g.grid_class, GridClass::FogVolume);
    assert_eq!(g.compression, "blosc + active-mask");
    assert_eq!(g.active_voxel_count(), 19_660);
    assert_eq!(g.active_bbox(), Some(([16, 1, 35], [85, 49, 65])));
    assert_eq!(g.leaves.len(), 131);
    let (lo, hi) = g.active_value_range().unwrap();
    assert!(lo > 0.0 && hi <= 1.0);
    assert!((g.index_to_world[0][0] - 0.1).abs() < 1e-7);
}

#[test]
fn sphere_half_level_set_version_222() {
    let Some(path) = external_data("sphere.vdb") else {
        return;
    };
    check_entry(&entry("shared:sphere.vdb"), &path);
    let g = vdb::read_grid(&path, None).unwrap();
    assert_eq!(g.name, "ls_sphere");
    assert_eq!(
        (g.file_version, g.stored_as_half, g.grid_class),
        (222, true, GridClass::LevelSet)
    );
    assert_eq!(g.active_voxel_count(), 270_638);
    assert_eq!(g.active_bbox(), Some(([-62; 3], [62; 3])));
    // Inside the sphere, far from the narrow band: inactive -background.
    assert_eq!(g.value_at([0, 0, 0]), -g.background);
    assert_eq!(g.value_at([200, 0, 0]), g.background);
}

/// The committed sphere (`tools/make_sphere_vdb.py`: OpenVDB 10 wrote it,
/// format 224, Blosc, half floats) holds the same voxels as openvdb.org's.
#[test]
fn committed_sphere_matches_openvdb() {
    let path = sample_data::committed("sphere.vdb");
    check_entry(&entry("data:sphere.vdb"), &path);
    let g = vdb::read_grid(&path, None).unwrap();
    assert_eq!(
        (g.file_version, g.stored_as_half, g.grid_class),
        (224, true, GridClass::LevelSet)
    );
    assert_eq!(g.active_voxel_count(), 270_638);
    assert_eq!(g.active_bbox(), Some(([-62; 3], [62; 3])));
    assert_eq!(g.value_at([0, 0, 0]), -g.background);
}

#[test]
fn cube_half_level_set_version_222() {
    let Some(path) = external_data("cube.vdb") else {
        return;
    };
    check_entry(&entry("shared:cube.vdb"), &path);
    let g = vdb::read_grid(&path, None).unwrap();
    assert_eq!(g.active_voxel_count(), 1_452_218);
    assert_eq!(g.active_bbox(), Some(([-112; 3], [112; 3])));
    assert_eq!(g.value_at([0, 0, 0]), -g.background);
}

#[test]
fn level_set_interior_is_negative_background() {
    for file in ["levelset_f32_blosc.vdb", "levelset_half_active.vdb"] {
        let g = vdb::read_grid(&fixture_dir().join(file), Some("surface")).unwrap();
        assert_eq!(g.grid_class, GridClass::LevelSet);
        // Center of the sphere (0.3, -0.2, 0.1) / 0.1 → voxel (3, -2, 1).
        assert_eq!(g.value_at([3, -2, 1]), -g.background, "{file}");
        assert!(
            g.tiles
                .iter()
                .any(|t| !t.active && t.value == -g.background),
            "{file}"
        );
        assert_eq!(g.value_at([3, -2, 100]), g.background, "{file}");
    }
}

#[test]
fn tiles_at_every_tree_level() {
    let g = vdb::read_grid(&fixture_dir().join("tiles_f32_zip.vdb"), None).unwrap();
    let has = |size: u32, active: bool, value: f32| {
        g.tiles
            .iter()
            .any(|t| t.size == size && t.active == active && t.value == value)
    };
    assert!(has(4096, true, 2.0), "active root tile");
    assert!(has(4096, false, 3.0), "inactive root tile");
    assert!(has(128, true, 1.0), "32^3-node tile");
    assert!(has(8, true, 0.75), "16^3-node tile");
    assert!(has(8, false, 0.5), "inactive 16^3-node tile");
    assert_eq!(g.value_at([-1, -1, -1]), 2.0);
    assert_eq!(g.value_at([5000, 17, 4000]), 3.0);
    assert_eq!(g.value_at([140, 3, 3]), 0.5);
    assert_eq!(g.value_at([-5000, 0, 0]), 0.0);
    // The index transform is a plain non-uniform scale.
    assert_eq!(g.index_to_world[0][0], 0.5);
    assert_eq!(g.index_to_world[1][1], 0.25);
    assert_eq!(g.index_to_world[2][2], 2.0);
}

#[test]
fn affine_transform_is_rotated() {
    let g = vdb::read_grid(&fixture_dir().join("affine_half_blosc.vdb"), None).unwrap();
    let m = g.index_to_world;
    assert!(m[0][1].abs() > 1e-3 && m[1][0].abs() > 1e-3, "{m:?}");
    assert_eq!([m[0][3], m[1][3], m[2][3]], [1.0, 2.0, 3.0]);
    // Columns keep the per-axis scales (0.1, 0.2, 0.05) under rotation.
    for (c, s) in [0.1, 0.2, 0.05].into_iter().enumerate() {
        let len = (0..3).map(|r| m[r][c] * m[r][c]).sum::<f64>().sqrt();
        assert!((len - s).abs() < 1e-12, "column {c}: {len}");
    }
}

#[test]
fn multi_grid_file_selection() {
    let path = fixture_dir().join("multi.vdb");
    let listed = vdb::list_grids(&path).unwrap();
    let names: Vec<&str> = listed.iter().map(|d| d.name.as_str()).collect();
    assert!(
        names.contains(&"heat[0]") && names.contains(&"heat[1]"),
        "{names:?}"
    );
    let vel = listed.iter().find(|d| d.name == "vel").unwrap();
    assert_eq!((vel.value_type.as_str(), vel.supported), ("vec3s", false));
    let mask = listed.iter().find(|d| d.name == "mask").unwrap();
    assert_eq!((mask.value_type.as_str(), mask.supported), ("bool", false));

    assert_eq!(vdb::read_grid(&path, None).unwrap().name, "density");
    let t = vdb::read_grid(&path, Some("temperature")).unwrap();
    assert_eq!(t.background, 300.0);
    assert_eq!(t.value_at([2, 4, 3]), 320.0);
    // Duplicated names: the plain name picks the first, `[N]` a given one.
    let h0 = vdb::read_grid(&path, Some("heat")).unwrap();
    let h1 = vdb::read_grid(&path, Some("heat[1]")).unwrap();
    assert_eq!(h0.name, "heat");
    assert_eq!(h0.value_at([1, 1, 1]), 10.0);
    assert_eq!(h1.value_at([2, 2, 2]), 20.0);
    // An instance reads its parent's tree.
    let d = vdb::read_grid(&path, Some("density")).unwrap();
    let i = vdb::read_grid(&path, Some("density_instance")).unwrap();
    assert_eq!(i.name, "density_instance");
    assert_eq!(d.leaves, i.leaves);
    // ScaleTranslateMap
    let near = |a: [f64; 4], b: [f64; 4]| (0..4).all(|c| (a[c] - b[c]).abs() < 1e-12);
    assert!(
        near(d.index_to_world[0], [0.2, 0.0, 0.0, 5.0]),
        "{:?}",
        d.index_to_world
    );
    assert!(
        near(d.index_to_world[2], [0.0, 0.0, 0.4, 7.0]),
        "{:?}",
        d.index_to_world
    );

    let err = vdb::read_grid(&path, Some("vel")).unwrap_err().to_string();
    assert!(
        err.contains("multi.vdb") && err.contains("`vel`") && err.contains("vec3s"),
        "{err}"
    );
    match vdb::read_grid(&path, Some("smoke")) {
        Err(VolumeError::GridNotFound {
            grid, available, ..
        }) => {
            assert_eq!(grid, "smoke");
            assert!(available.iter().any(|n| n == "density"), "{available:?}");
        }
        other => panic!("expected GridNotFound, got {other:?}"),
    }
}

#[test]
fn errors_name_file_grid_and_offset() {
    let path = fixture_dir().join("fog_f32_blosc.vdb");
    let bytes = std::fs::read(&path).unwrap();
    let cut = &bytes[..bytes.len() - 1000];
    let err = vdb::parse_grid(&path, cut, None).unwrap_err().to_string();
    assert!(err.contains("fog_f32_blosc.vdb"), "{err}");
    assert!(
        err.contains("grid `density`") && err.contains("offset"),
        "{err}"
    );

    let err = vdb::parse_grid(Path::new("x.vdb"), b"not a vdb file at all", None).unwrap_err();
    assert!(err.to_string().contains("not an OpenVDB file"), "{err}");

    let missing = Path::new("/nonexistent/dir/none.vdb");
    assert!(matches!(
        vdb::read_grid(missing, None),
        Err(VolumeError::Io { .. })
    ));

    let mut old = bytes.clone();
    old[8..12].copy_from_slice(&221u32.to_le_bytes());
    let err = vdb::parse_grid(&path, &old, None).unwrap_err().to_string();
    assert!(err.contains("221"), "{err}");
}

#[test]
fn blosc_frames_from_python_blosc() {
    use vdb::blosc;
    let text = std::fs::read_to_string(fixture_dir().join("blosc_frames.json")).unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    let payloads: Vec<Vec<u8>> = v["payloads"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| base64(p.as_str().unwrap()))
        .collect();
    let frames = v["frames"].as_array().unwrap();
    assert!(frames.len() >= 30);
    for fr in frames {
        let data = &payloads[fr["payload"].as_u64().unwrap() as usize];
        let frame = base64(fr["frame"].as_str().unwrap());
        let what = format!(
            "{} / {} shuffle / typesize {}",
            fr["codec"], fr["shuffle"], fr["typesize"]
        );
        let out = blosc::decompress(&frame, data.len()).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(out == *data, "{what}: wrong bytes");
        assert!(blosc::decompress(&frame, data.len() + 1).is_err(), "{what}");
        for cut in [1, frame.len() / 2, frame.len() - 1] {
            assert!(
                blosc::decompress(&frame[..cut], data.len()).is_err(),
                "{what} cut {cut}"
            );
        }
    }
}

fn base64(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("bad base64"),
    };
    let mut out = Vec::new();
    let bytes: Vec<u8> = s.bytes().filter(|&c| c != b'=').collect();
    for chunk in bytes.chunks(4) {
        let mut acc = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            acc |= (val(c) as u32) << (18 - 6 * i);
        }
        for i in 0..chunk.len() - 1 {
            out.push((acc >> (16 - 8 * i)) as u8);
        }
    }
    out
}

//! NanoVDB reader against the OpenVDB reader: committed `.nvdb` fixtures
//! (made by `nanovdb_convert` 32.4 from the committed `.vdb` fixtures of
//! `fixtures/vdb`, see `fixtures/nanovdb/README.md`) must hold the same
//! voxels as their sources; and, when `nanovdb_convert` and `nanovdb_print`
//! are installed, the real files of `data/` and the external data converted
//! at every quantisation and codec, against their `.vdb` voxels and against
//! what `nanovdb_print` reports. Those tests skip with a message without
//! the tools, unless `FOGBANK_REQUIRE_NANOVDB=1` (set by `.ci/run`).

use std::path::{Path, PathBuf};

use fogbank_volume::loaders::nanovdb;
use fogbank_volume::loaders::vdb::{self, VdbGrid};

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

//! `fogbank convert`: a pbrt scene to TOML and Mitsuba XML (with its notes
//! on stderr), which `render` then reads; a volume between formats; bad
//! input named in the error.

use crate::support;

use fogbank::testing::sample_data;
use support::{fogbank, run_fails_naming, run_ok, tmp_dir};

fn pbrt(name: &str) -> String {
    format!("{}/../scene/tests/pbrt/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn convert_writes_scenes_that_render() {
    let dir = tmp_dir("convert_scenes");
    let toml = dir.join("fog_sphere.toml");
    let xml = dir.join("fog_sphere.xml");
    for out in [&toml, &xml] {
        let said = run_ok(fogbank().args([
            "convert",
            &pbrt("fog_sphere.pbrt"),
            "-o",
            out.to_str().unwrap(),
        ]));
        let stdout = String::from_utf8_lossy(&said.stdout);
        assert!(stdout.contains("1 media, 1 lights, 2 shapes"), "{stdout}");
    }
    let said = run_ok(fogbank().args([
        "convert",
        &pbrt("fog_sphere.pbrt"),
        "-o",
        xml.to_str().unwrap(),
    ]));
    assert!(String::from_utf8_lossy(&said.stderr).contains("note: camera.near_clip"));
    assert!(dir.join("fog_sphere_medium0.vol").is_file());
    for scene in [&toml, &xml] {
        let exr = scene.with_extension("exr");
        run_ok(fogbank().args([
            "render",
            scene.to_str().unwrap(),
            "-o",
            exr.to_str().unwrap(),
            "--spp",
            "2",
        ]));
        assert!(exr.is_file());
    }
}

#[test]
fn convert_moves_a_grid_between_volume_formats() {
    let dir = tmp_dir("convert_volumes");
    let dragon = sample_data::committed("dragon.vdb");
    let nvdb = dir.join("dragon.nvdb");
    let said = run_ok(fogbank().args([
        "convert",
        dragon.to_str().unwrap(),
        "-o",
        nvdb.to_str().unwrap(),
        "--codec",
        "blosc",
    ]));
    assert!(String::from_utf8_lossy(&said.stdout).contains("19660 active voxels"));
    let info = run_ok(fogbank().args(["info", nvdb.to_str().unwrap()]));
    assert!(String::from_utf8_lossy(&info.stdout).contains("active voxels 19660"));
}

#[test]
fn convert_names_the_bad_file() {
    let dir = tmp_dir("convert_bad");
    let out = dir.join("x.toml");
    let out = out.to_str().unwrap();
    run_fails_naming(
        fogbank().args(["convert", "scene.blend", "-o", out]),
        "scene.blend",
    );
    run_fails_naming(
        fogbank().args(["convert", "missing.pbrt", "-o", out]),
        "missing.pbrt",
    );
    let deep = dir.join("no/such/folder/y.toml");
    run_fails_naming(
        fogbank().args([
            "convert",
            &pbrt("offcentre.pbrt"),
            "-o",
            deep.to_str().unwrap(),
        ]),
        "y.toml",
    );
    run_fails_naming(
        fogbank().args([
            "convert",
            &pbrt("offcentre.pbrt"),
            "-o",
            out,
            "--codec",
            "lzma",
        ]),
        "--codec lzma",
    );
}

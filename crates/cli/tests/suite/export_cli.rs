//! `fogbank export`: a scene's medium written as .vdb and .nvdb, which
//! `fogbank info` then reports as it reports the medium's source file.

use crate::support;

use fogbank::testing::sample_data;
use support::{fogbank, run_fails_naming, run_ok, tmp};

/// A scene file of the dragon named `name` (one per test: tests run at once).
fn dragon_scene(name: &str) -> std::path::PathBuf {
    let scene = tmp(name);
    let dragon = sample_data::committed("dragon.vdb");
    let text = format!(
        "[[media]]\ndensity = {{ vdb = \"{}\" }}\n",
        dragon.display()
    );
    std::fs::write(&scene, text).unwrap();
    scene
}

#[test]
fn export_writes_what_info_reads() {
    let scene = dragon_scene("export_dragon.toml");
    for (file, extra) in [
        ("export_dragon.vdb", vec!["--codec", "zip", "--half"]),
        (
            "export_dragon.nvdb",
            vec!["--codec", "blosc", "--quantise", "fp16"],
        ),
        ("export_dragon_f.nvdb", vec![]),
    ] {
        let out = tmp(file);
        let mut cmd = fogbank();
        cmd.args([
            "export",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        let said = run_ok(cmd.args(&extra));
        let said = String::from_utf8_lossy(&said.stdout).to_string();
        assert!(said.contains("19660 active voxels"), "{said}");
        let info = run_ok(fogbank().args(["info", out.to_str().unwrap()]));
        let text = String::from_utf8_lossy(&info.stdout);
        assert!(text.contains("active voxels 19660"), "{file}: {text}");
        // The file's index frame is fogbank's (the world placement is the
        // medium's): the box is the dragon's, moved.
        assert_eq!(bbox_extent(&text), [70, 49, 31], "{file}: {text}");
    }
}

/// Edge lengths of the `index bbox [a, b, c] – [d, e, f]` line.
fn bbox_extent(text: &str) -> [i64; 3] {
    let line = text.lines().find(|l| l.contains("index bbox")).unwrap();
    let nums: Vec<i64> = line
        .split(|c: char| !(c.is_ascii_digit() || c == '-'))
        .filter_map(|t| t.parse().ok())
        .collect();
    [0, 1, 2].map(|k| nums[k + 3] - nums[k] + 1)
}

#[test]
fn export_refuses_bad_options() {
    let scene = dragon_scene("export_bad.toml");
    let s = scene.to_str().unwrap();
    let out = tmp("export_bad.vdb");
    let o = out.to_str().unwrap();
    for (option, needle) in [
        (["--codec", "lzma"], "--codec lzma"),
        (["--grid", "vel"], "--grid vel"),
        (["--quantise", "fp8"], "quantisation"),
        (["--medium", "2"], "has 1 media"),
        (["--grid", "temperature"], "temperature"),
    ] {
        run_fails_naming(fogbank().args(["export", s, "-o", o]).args(option), needle);
    }
}

//! A medium exported as a volume file and loaded again is the same medium:
//! a float `.vdb` or `.nvdb` of a medium read from a file, placed with a
//! `to_world`, renders bit for bit as the original (the transform folded
//! into the file's map), and a procedural medium exports the voxels it
//! renders.

use crate::support::same_image;

use fogbank_math::sample_data;
use fogbank_render::{parse_scene, SceneDesc};
use fogbank_scene::export::{export_desc, medium_grid, ExportGrid, ExportOptions};
use fogbank_volume::loaders::{nanovdb, vdb};
use fogbank_volume::writers::{Codec, NanoValue};
use same_image::{assert_same_image, transmittance_image};
use std::path::{Path, PathBuf};

const CAMERA: &str = "[camera]\nfrom = [6.0, 4.0, 14.0]\nto = [6.0, 2.5, 4.5]\nfov = 40.0\nwidth = 16\nheight = 16\n";

/// A scene of one medium with density `density` and `extra` keys.
fn scene(density: &str, extra: &str) -> SceneDesc {
    let text = format!(
        "{CAMERA}[[media]]\ndensity = {density}\nsigma_t_scale = 8.0\n{extra}\n\
         [integrator]\ntype = \"transmittance\"\nestimator = \"ratio_tracking\"\n"
    );
    parse_scene(&text, "test", &[]).unwrap()
}

fn out_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("fogbank-export-{}-{name}", std::process::id()))
}

#[test]
fn exported_medium_renders_as_the_original() {
    let dragon = sample_data::committed("dragon.vdb");
    let placement =
        "to_world = { translate = [0.25, -0.5, 0.125], rotate = [0.0, 1.0, 0.0, 10.0] }";
    let original = scene(&format!("{{ vdb = \"{}\" }}", dragon.display()), placement);
    let want = transmittance_image(original.clone());
    for (file, key, codec) in [
        ("dragon.vdb", "vdb", Codec::Zip),
        ("dragon.nvdb", "nvdb", Codec::Blosc),
    ] {
        let out = out_path(file);
        let options = ExportOptions {
            codec,
            ..Default::default()
        };
        let done = export_desc(&original, Path::new("."), &out, &options).unwrap();
        assert_eq!(done.grid, "density");
        let back = scene(&format!("{{ {key} = \"{}\" }}", out.display()), "");
        let got = transmittance_image(back);
        std::fs::remove_file(&out).ok();
        assert_same_image(&got, &want, file);
    }
}

#[test]
fn procedural_medium_exports_its_voxels() {
    let desc = scene(
        "{ procedural = \"cloud\", resolution = 32, seed = 3 }",
        "to_world = { scale = 4.0, translate = [4.0, 1.0, 3.0] }",
    );
    let grid = medium_grid(&desc, Path::new("."), &ExportOptions::default()).unwrap();
    assert!(grid.active_voxel_count() > 1000);
    for (file, value) in [
        ("cloud.nvdb", NanoValue::Float),
        ("cloud8.nvdb", NanoValue::Fp8),
    ] {
        let out = out_path(file);
        let options = ExportOptions {
            value,
            ..Default::default()
        };
        let done = export_desc(&desc, Path::new("."), &out, &options).unwrap();
        let back = nanovdb::read_grid(&out, None).unwrap();
        std::fs::remove_file(&out).ok();
        assert_eq!(done.active_voxels, grid.active_voxel_count());
        assert_eq!(back.active_voxel_count(), grid.active_voxel_count());
        assert_eq!(back.index_to_world, grid.index_to_world);
        if value == NanoValue::Float {
            let (a, b) = (back.active_value_sum(), grid.active_value_sum());
            assert!((a - b).abs() <= 1e-12 * b, "{a} vs {b}");
        }
    }
    let out = out_path("cloud.vdb");
    let half = ExportOptions {
        half: true,
        ..Default::default()
    };
    export_desc(&desc, Path::new("."), &out, &half).unwrap();
    let back = vdb::read_grid(&out, None).unwrap();
    std::fs::remove_file(&out).ok();
    assert!(back.stored_as_half);
    assert_eq!(back.active_voxel_count(), grid.active_voxel_count());
}

#[test]
fn export_errors_name_the_problem() {
    let desc = scene("{ procedural = \"cloud\", resolution = 16 }", "");
    let err = |out: &str, o: ExportOptions| {
        export_desc(&desc, Path::new("."), &out_path(out), &o)
            .err()
            .unwrap()
            .0
    };
    assert!(err("x.png", ExportOptions::default()).contains(".vdb or .nvdb"));
    let e = err(
        "x.vdb",
        ExportOptions {
            medium: 3,
            ..Default::default()
        },
    );
    assert!(e.contains("has 1 media"), "{e}");
    let e = err(
        "x.vdb",
        ExportOptions {
            grid: ExportGrid::Temperature,
            ..Default::default()
        },
    );
    assert!(e.contains("temperature"), "{e}");
    let e = err(
        "x.nvdb",
        ExportOptions {
            half: true,
            ..Default::default()
        },
    );
    assert!(e.contains("half"), "{e}");
    let e = err(
        "x.vdb",
        ExportOptions {
            value: NanoValue::Fp8,
            ..Default::default()
        },
    );
    assert!(e.contains("quantisation"), "{e}");
}

#[test]
fn temperature_grid_exports_as_its_own_grid() {
    let desc = scene(
        "{ procedural = \"explosion\", resolution = 24, seed = 3 }",
        "emission = { temperature = { procedural = \"explosion\", quantity = \"temperature\", resolution = 24, seed = 3 }, scale = 40.0 }",
    );
    let out = out_path("temperature.vdb");
    let options = ExportOptions {
        grid: ExportGrid::Temperature,
        codec: Codec::Blosc,
        ..Default::default()
    };
    let done = export_desc(&desc, Path::new("."), &out, &options).unwrap();
    let back = vdb::read_grid(&out, Some("temperature")).unwrap();
    std::fs::remove_file(&out).ok();
    assert_eq!(done.grid, "temperature");
    assert_eq!(back.active_voxel_count(), done.active_voxels);
    let (_, hi) = back.active_value_range().unwrap();
    assert!(hi > 500.0, "temperatures in kelvin, hottest {hi}");
}

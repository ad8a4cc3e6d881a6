//! End-to-end tests of the `fogbank` binary.

use std::path::{Path, PathBuf};
use std::process::Command;

fn fogbank() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fogbank"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join("fogbank_cli_test");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn shared(name: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!("skipping: {} not found", p.display());
        None
    }
}

const SMALL: [&str; 6] = [
    "--set",
    "camera.width=40",
    "--set",
    "camera.height=30",
    "--set",
    "media.0.density.resolution=32",
];

#[test]
fn default_render_writes_exr_with_variance_png_and_stats() {
    let dir = tmp("default");
    std::fs::create_dir_all(&dir).unwrap();
    let out = fogbank()
        .current_dir(&dir)
        .args(["render", "--quiet", "--spp", "4", "--stats", "stats.json"])
        .args(SMALL)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("fogbank.png").exists());
    let image = exr::prelude::read_all_flat_layers_from_file(dir.join("fogbank.exr")).unwrap();
    let layer = &image.layer_data[0];
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    for n in ["R", "G", "B", "variance.R", "variance.G", "variance.B"] {
        assert!(
            names.iter().any(|x| x == n),
            "missing channel {n} in {names:?}"
        );
    }
    assert_eq!(layer.size.0 * layer.size.1, 40 * 30);
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("stats.json")).unwrap()).unwrap();
    for key in [
        "integrator",
        "estimator",
        "width",
        "height",
        "spp",
        "seed",
        "threads",
        "render_seconds",
        "mean",
        "lookups_per_pixel",
        "nan_pixels",
        "inf_pixels",
        "peak_memory_bytes",
    ] {
        assert!(stats.get(key).is_some(), "stats.json lacks `{key}`");
    }
    assert_eq!(stats["spp"], 4);
    assert_eq!(stats["width"], 40);
    let mean = stats["mean"][0].as_f64().unwrap();
    assert!(mean > 0.0 && mean < 1.0, "transmittance image mean {mean}");
    assert!(stats["lookups_per_pixel"].as_f64().unwrap() > 0.0);
}

#[test]
fn bad_set_key_is_an_error_naming_it() {
    let out = fogbank()
        .args([
            "render",
            "--quiet",
            "-o",
            tmp("x.png").to_str().unwrap(),
            "--set",
            "integrator.estimatr=x",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("estimatr") && !err.contains("panicked"),
        "{err}"
    );
}

#[test]
fn info_reports_the_dragon() {
    let Some(p) = shared("dragon.vdb") else {
        return;
    };
    let out = fogbank()
        .args(["info", p.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("active voxels 19660"), "{text}");
    assert!(text.contains("[16, 1, 35] – [85, 49, 65]"), "{text}");
}

#[test]
fn info_reports_vol_and_rejects_garbage() {
    if let Some(p) = shared("sigmat.vol") {
        let out = fogbank()
            .args(["info", p.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(out.status.success());
        assert!(String::from_utf8_lossy(&out.stdout).contains("16×16×16"));
    }
    let bad = tmp("garbage.vdb");
    std::fs::write(&bad, b"this is not a vdb file at all").unwrap();
    let out = fogbank()
        .args(["info", bad.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("garbage.vdb") && !err.contains("panicked"),
        "{err}"
    );
}

#[test]
fn renders_a_vdb_scene_file_with_relative_paths() {
    let Some(p) = shared("dragon.vdb") else {
        return;
    };
    let dir = tmp("vdbscene");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(&p, dir.join("dragon.vdb")).unwrap();
    std::fs::write(
        dir.join("scene.toml"),
        "[camera]\nfrom = [3.0, 4.0, 12.0]\nto = [5.0, 2.5, 5.0]\nwidth = 32\nheight = 24\n\
         [[media]]\ndensity = { vdb = \"dragon.vdb\" }\nsigma_t_scale = 10.0\n\
         [integrator]\nestimator = \"analytic_trilinear\"\n[render]\nspp = 1\n",
    )
    .unwrap();
    let out = fogbank()
        .args([
            "render",
            "--quiet",
            dir.join("scene.toml").to_str().unwrap(),
            "-o",
            dir.join("d.exr").to_str().unwrap(),
            "--stats",
            dir.join("s.json").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
    let mean = stats["mean"][0].as_f64().unwrap();
    assert!(mean < 1.0, "the dragon must be visible (mean T {mean})");
}

#[test]
fn ctrl_c_stops_and_still_writes_the_image() {
    let dir = tmp("interrupt");
    std::fs::create_dir_all(&dir).unwrap();
    let _ = std::fs::remove_file(dir.join("i.exr"));
    let mut child = fogbank()
        .current_dir(&dir)
        .args([
            "render", "--quiet", "--spp", "1000000", "-o", "i.exr", "--stats", "i.json",
        ])
        .args(SMALL)
        .spawn()
        .unwrap();
    // Wait until the scene is built and rendering has begun (the stats file
    // does not exist before), then interrupt.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let status = child.wait().unwrap();
    assert!(
        status.success(),
        "interrupted render must exit cleanly, got {status}"
    );
    assert!(dir.join("i.exr").exists(), "no image written after Ctrl-C");
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("i.json")).unwrap()).unwrap();
    assert_eq!(stats["interrupted"], true);
    assert!(stats["spp"].as_u64().unwrap() < 1_000_000);
}

#[test]
fn stats_reports_no_bias_for_an_unbiased_estimator_and_report_gathers_it() {
    let dir = tmp("stats");
    let _ = std::fs::remove_dir_all(&dir);
    let out = fogbank()
        .args([
            "stats",
            "--estimator",
            "ratio_tracking",
            "--runs",
            "512",
            "--reference-estimator",
            "analytic_trilinear",
        ])
        .args(["--out", dir.join("rt").to_str().unwrap()])
        .args(SMALL)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rt/summary.json")).unwrap())
            .unwrap();
    for key in [
        "mean_abs_bias",
        "mean_bias",
        "mean_std",
        "rmse",
        "ms_per_frame",
        "lookups_per_pixel",
        "runs",
    ] {
        assert!(
            s.get(key).is_some_and(|v| !v.is_null()),
            "summary.json lacks `{key}`"
        );
    }
    let (bias, se) = (
        s["mean_bias"].as_f64().unwrap(),
        s["mean_bias_se"].as_f64().unwrap(),
    );
    assert!(
        se > 0.0 && bias.abs() < 4.0 * se,
        "mean bias {bias} (se {se})"
    );
    assert!(dir.join("rt/maps.png").exists() && dir.join("rt/stats.exr").exists());
    let out = fogbank()
        .args(["report", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success());
    let page = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(page.contains("rt/maps.png") && page.contains("mean_abs_bias"));
}

#[test]
fn compare_flags_a_biased_render_and_reports_every_metric() {
    let dir = tmp("compare");
    std::fs::create_dir_all(&dir).unwrap();
    let render = |name: &str, estimator: &str, extra: &[&str]| {
        let out = fogbank()
            .args([
                "render",
                "--quiet",
                "--spp",
                "512",
                "-o",
                dir.join(name).to_str().unwrap(),
            ])
            .args(["--set", &format!("integrator.estimator={estimator}")])
            .args(extra)
            .args(SMALL)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    render("ref.exr", "ratio_tracking", &[]);
    render(
        "biased.exr",
        "ray_marching",
        &["--set", "integrator.samples=2"],
    );
    let compare = |a: &str, b: &str| {
        let out = fogbank()
            .args([
                "compare",
                dir.join(a).to_str().unwrap(),
                dir.join(b).to_str().unwrap(),
                "--json",
            ])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let same = compare("ref.exr", "ref.exr");
    assert_eq!(same["rmse"].as_f64(), Some(0.0), "{same}");
    assert_eq!(same["ztest"]["pass"], true, "{same}");
    let biased = compare("ref.exr", "biased.exr");
    for key in ["rmse", "relmse", "smape", "flip", "ztest"] {
        assert!(biased.get(key).is_some(), "no `{key}` in {biased}");
    }
    assert!(biased["rmse"].as_f64().unwrap() > 0.0);
    assert_eq!(
        biased["ztest"]["pass"], false,
        "two-sample ray marching must be flagged: {}",
        biased["ztest"]
    );
}

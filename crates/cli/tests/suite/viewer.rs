//! `fogbank view` as a person uses it: a real window under Xvfb (Mesa's
//! lavapipe renders both egui and, with `--device gpu`, the scene), driven
//! by a scripted session that orbits, switches the estimator, saves
//! screenshots, the image and the scene. The screenshots must show the
//! volume and change after each step; the saved scene must re-render with
//! `fogbank render` to an image that passes the per-pixel z-test against
//! the viewer's accumulated image at equal spp.
//!
//! Needs `xvfb-run` (Debian's `xvfb` and `xauth`); without it the test is
//! skipped, unless `FOGBANK_REQUIRE_DISPLAY=1` (set by `.ci/run`).

use std::path::{Path, PathBuf};
use std::process::Command;

fn fogbank() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fogbank"))
}

const SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenes/transmittance.toml"
);

const SCRIPT: &str = r#"
[[step]]
wait_spp = 4
[[step]]
screenshot = "shot_0.png"
[[step]]
orbit = [60.0, 20.0]
[[step]]
wait_spp = 4
[[step]]
screenshot = "shot_1.png"
[[step]]
set = ["integrator.estimator=track_length"]
[[step]]
wait_spp = 8
[[step]]
save_image = "view.exr"
[[step]]
save_scene = "view.toml"
[[step]]
overlay = "relative_error"
[[step]]
screenshot = "shot_2.png"
[[step]]
key = "H"
[[step]]
screenshot = "shot_3.png"
[[step]]
key = "Ctrl+S"
[[step]]
quit = true
"#;

fn xvfb_run() -> Option<PathBuf> {
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|d| d.join("xvfb-run"))
            .find(|p| p.exists())
    });
    if found.is_none() {
        if std::env::var("FOGBANK_REQUIRE_DISPLAY").as_deref() == Ok("1") {
            panic!("FOGBANK_REQUIRE_DISPLAY=1 but xvfb-run is not installed");
        }
        eprintln!("SKIPPED (no xvfb-run: install Debian's xvfb and xauth)");
    }
    found
}

/// RGBA pixels of a screenshot.
fn shot(path: &Path) -> image::RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

fn fraction_differing(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let n = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 8))
        .count();
    n as f64 / (a.width() * a.height()) as f64
}

fn scripted_session(device: &str) {
    let Some(xvfb) = xvfb_run() else { return };
    let dir = std::env::temp_dir().join(format!("fogbank_viewer_test_{device}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("steps.toml"), SCRIPT).unwrap();
    let runtime = dir.join("xdg");
    std::fs::create_dir_all(&runtime).unwrap();
    let out = Command::new(xvfb)
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_fogbank"))
        .args(["view", SCENE, "--device", device, "--spp", "8"])
        .args(["--set", "camera.width=160", "--set", "camera.height=120"])
        .args(["--threads", "2", "--script-timeout", "240", "--script"])
        .arg(dir.join("steps.toml"))
        .env("XDG_RUNTIME_DIR", &runtime)
        .current_dir(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "fogbank view failed: {err}");

    // Screenshots: the window, with the volume in view, changing each step.
    let shots: Vec<_> = (0..4)
        .map(|i| shot(&dir.join(format!("shot_{i}.png"))))
        .collect();
    for (i, s) in shots.iter().enumerate() {
        assert!(
            s.width() >= 640 && s.height() >= 400,
            "shot {i}: {:?}",
            s.dimensions()
        );
    }
    // The transmittance view: a dark cloud in front of a white background.
    let (white, dark) = shots[0].pixels().fold((0, 0), |(w, d), p| {
        let l = p.0[0] as u32 + p.0[1] as u32 + p.0[2] as u32;
        (w + (l > 740) as u32, d + (l < 150) as u32)
    });
    let area = shots[0].width() * shots[0].height();
    assert!(
        white > area / 20,
        "no white background in shot 0 ({white} px)"
    );
    assert!(dark > area / 200, "no dark volume in shot 0 ({dark} px)");
    // Orbit, estimator + overlay, help overlay: each step changes the window.
    for i in 1..4 {
        let f = fraction_differing(&shots[i - 1], &shots[i]);
        assert!(
            f > 0.01,
            "shot {i} hardly differs from shot {} ({f})",
            i - 1
        );
    }

    // Ctrl+S saved the image under the panel's default name, in the
    // working directory.
    assert!(
        dir.join("fogbank_view.exr").exists(),
        "Ctrl+S wrote no image"
    );

    // The saved scene re-renders to the viewer's image at equal spp.
    let saved = std::fs::read_to_string(dir.join("view.toml")).unwrap();
    assert!(
        saved.contains("spp = 8") && saved.contains("track_length"),
        "{saved}"
    );
    let o = fogbank()
        .args(["render", "--quiet", "--device", device])
        .arg(dir.join("view.toml"))
        .arg("-o")
        .arg(dir.join("render.exr"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = fogbank()
        .args(["compare", "--metric", "ztest", "--json"])
        .arg(dir.join("view.exr"))
        .arg(dir.join("render.exr"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let z: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(z["ztest"]["pass"], true, "{z}");
}

#[test]
fn scripted_session_on_the_cpu_round_trips_the_scene() {
    scripted_session("cpu");
}

#[test]
fn scripted_session_on_the_gpu_round_trips_the_scene() {
    if fogbank::testing::test_gpu().is_none() {
        return;
    }
    scripted_session("gpu");
}

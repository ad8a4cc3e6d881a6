//! Helpers of the `fogbank` binary's end-to-end tests.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Output, Stdio};
use std::time::{Duration, Instant};
pub fn fogbank() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fogbank"))
}

pub fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join("fogbank_cli_test");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// [`tmp`], created as a folder.
pub fn tmp_dir(name: &str) -> PathBuf {
    let dir = tmp(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `cmd` and asserts that it succeeded, showing its stderr if not.
pub fn run_ok(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs `cmd` and asserts that it failed with a message naming `needle`,
/// not with a panic.
pub fn run_fails_naming(cmd: &mut Command, needle: &str) {
    let out = cmd.output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(needle) && !err.contains("panicked"), "{err}");
}

pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The cumulus's transmittance view, the scene of the estimator tests.
pub const TRANSMITTANCE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenes/transmittance.toml"
);

pub const SMALL: [&str; 6] = [
    "--set",
    "camera.width=40",
    "--set",
    "camera.height=30",
    "--set",
    "media.0.density.resolution=32",
];

/// Whether process `pid` has installed its SIGINT handler (bit 2 of
/// `SigCgt` in `/proc/PID/status`). Without `/proc` (not Linux) there is no
/// such evidence; then it waits 1.5 s and assumes so.
pub fn render_started(pid: u32) -> bool {
    if !Path::new("/proc/self/status").exists() {
        std::thread::sleep(Duration::from_millis(1500));
        return true;
    }
    let Ok(status) = std::fs::read_to_string(format!("/proc/{pid}/status")) else {
        return false;
    };
    status
        .lines()
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| mask & (1 << (2 - 1)) != 0)
}

/// Starts `fogbank ARGS` in `dir`, waits until it renders, sends Ctrl-C
/// (SIGINT) and returns its exit status and stderr.
pub fn render_then_ctrl_c(dir: &Path, args: &[&str]) -> (ExitStatus, String) {
    let mut child = fogbank()
        .current_dir(dir)
        .args(args)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read stderr on a thread so that a full pipe can never block the child.
    let mut pipe = child.stderr.take().unwrap();
    let stderr = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = pipe.read_to_string(&mut text);
        text
    });
    // The progress bar is hidden when stderr is not a terminal, so the first
    // evidence of rendering is the Ctrl-C handler, installed once the scene
    // is built, right before the first pass.
    let deadline = Instant::now() + Duration::from_secs(120);
    while !render_started(child.id()) {
        if let Some(status) = child.try_wait().unwrap() {
            panic!(
                "render exited before it was interrupted ({status}): {}",
                stderr.join().unwrap()
            );
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("render showed no sign of starting within 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let status = child.wait().unwrap();
    (status, stderr.join().unwrap())
}

/// Writes an animated scene into `dir`: an 8³ u8 volume per frame in
/// `written` (`d_{frame}.raw`, a different pattern each), a `width`×`height`
/// camera, `integrator` (the body of `[integrator]`) and `frames` frames.
/// Returns the scene's path.
pub fn animated_raw_scene(
    dir: &Path,
    written: &[u32],
    (width, height): (u32, u32),
    integrator: &str,
    frames: u32,
) -> PathBuf {
    for &f in written {
        let bytes: Vec<u8> = (0..512)
            .map(|i| ((i * 7 + f as usize * 13) % 200) as u8)
            .collect();
        std::fs::write(dir.join(format!("d_{f}.raw")), bytes).unwrap();
    }
    let scene = dir.join("anim.toml");
    std::fs::write(
        &scene,
        format!(
            "[camera]\nwidth = {width}\nheight = {height}\n[[media]]\n\
             density = {{ raw = \"d_{{frame}}.raw\", dims = [8, 8, 8], type = \"u8\" }}\n\
             sigma_t_scale = 0.05\n[[lights]]\ntype = \"constant\"\nradiance = [1.0, 1.0, 1.0]\n\
             [integrator]\n{integrator}\n[animation]\nframes = {frames}\n"
        ),
    )
    .unwrap();
    scene
}

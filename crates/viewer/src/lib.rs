//! `fogbank view`: an interactive window that renders a scene
//! progressively — on the GPU backend when an adapter exists, on the CPU
//! otherwise or when asked — and restarts accumulation on every change:
//! orbit / pan / zoom, integrator, estimator and their options, the
//! medium, the light, exposure and tone curve; live statistics; a
//! relative-error overlay; two estimators side by side at equal time;
//! saving the image (EXR with variance, or PNG) and the scene (TOML that
//! `fogbank render` reproduces exactly). The window is eframe's (winit +
//! wgpu + egui); a script ([`script`]) plays the same actions for tests.
//!
//! Modules in layers, each importing only those before it: `session` (one scene
//! rendering progressively on a worker thread, publishing snapshots of its film) and
//! `orbit` (orbit, pan and zoom of a look-at camera) → `display` (snapshots to pixels:
//! the tone-mapped image, the relative-error map, the split screen) → `script`
//! (scripted sessions) → `controls` (the control panel) → `app` (the window and the
//! dispatch of every action) → `shortcuts` (keyboard shortcuts and the help overlay).

pub mod app;
pub mod controls;
pub mod display;
pub mod orbit;
pub mod script;
pub mod session;
pub mod shortcuts;

use app::{ViewConfig, Viewer};
use eframe::egui;
use session::Backend;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Where `fogbank view` renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeviceChoice {
    /// The GPU when an adapter exists, else the CPU.
    Auto,
    Cpu,
    Gpu,
}

pub struct ViewOptions {
    pub scene: Option<PathBuf>,
    pub overrides: Vec<String>,
    pub device: DeviceChoice,
    pub threads: Option<usize>,
    /// Stop accumulating at this many samples per pixel.
    pub max_spp: u32,
    pub script: Option<PathBuf>,
    pub script_timeout: Duration,
}

/// Opens the window and returns when it closes; an error when the scene or
/// script is bad, no window can be opened, or a script step failed.
pub fn run(o: ViewOptions) -> Result<(), String> {
    let scene = fogbank::load_scene(o.scene.as_deref(), &o.overrides).map_err(|e| e.to_string())?;
    let base = o
        .scene
        .as_ref()
        .and_then(|p| p.parent().map(|p| p.to_path_buf()))
        .unwrap_or_else(|| PathBuf::from("."));
    let origin = o
        .scene
        .as_ref()
        .map_or("built-in scene".to_string(), |p| p.display().to_string());
    let script = o
        .script
        .as_ref()
        .map(|p| script::load(p).map(|a| a.into_iter().collect()))
        .transpose()?;
    let cpu_threads = o
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()));
    let gpu = match o.device {
        DeviceChoice::Cpu => None,
        DeviceChoice::Auto => fogbank::Gpu::new().ok().map(Arc::new),
        DeviceChoice::Gpu => Some(Arc::new(
            fogbank::Gpu::new().map_err(|e| format!("--device gpu: {e}"))?,
        )),
    };
    let backend = match &gpu {
        Some(g) if o.device != DeviceChoice::Cpu => Backend::Gpu(g.clone()),
        _ => Backend::Cpu {
            threads: cpu_threads,
        },
    };
    let failure = Arc::new(Mutex::new(None));
    let cfg = ViewConfig {
        desc: scene.desc.clone(),
        base,
        origin: origin.clone(),
        backend,
        gpu,
        cpu_threads,
        max_spp: o.max_spp,
        script,
        script_timeout: o.script_timeout,
        failure: failure.clone(),
    };
    let (w, h) = (scene.camera.width as f32, scene.camera.height as f32);
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(format!("fogbank view — {origin}"))
            .with_inner_size([(w + 300.0).max(960.0), (h + 60.0).max(640.0)]),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    drop(scene);
    eframe::run_native(
        "fogbank view",
        options,
        Box::new(move |cc| Ok(Box::new(Viewer::new(cfg, &cc.egui_ctx)))),
    )
    .map_err(|e| format!("cannot open the viewer window: {e}"))?;
    let failed = failure.lock().unwrap().take();
    match failed {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

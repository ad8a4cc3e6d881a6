//! The viewer's window: the image, the control panel, the status line, the
//! help overlay, and the dispatch of every [`Action`] (from mouse, keys,
//! widgets or a script) to the scene and the render sessions.

use crate::controls::{self, PanelState};
use crate::display::{self, Overlay};
use crate::orbit;
use crate::script::Action;
use crate::session::{Backend, Session, Snapshot};
use eframe::egui;
use fogbank::desc::SceneDesc;
use fogbank::image::{write_exr, write_png, ToneMapping};
use fogbank::{parse_scene, Scene};
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Where a screenshot callback leaves the result of writing its file.
type ScreenshotSlot = Arc<Mutex<Option<Result<(), String>>>>;

/// How the viewer was started.
pub struct ViewConfig {
    pub desc: SceneDesc,
    /// The folder relative file names in the scene resolve against.
    pub base: PathBuf,
    pub origin: String,
    pub backend: Backend,
    /// The GPU, when one was found (the panel offers it).
    pub gpu: Option<Arc<fogbank::Gpu>>,
    pub cpu_threads: usize,
    /// Stop accumulating at this many samples per pixel.
    pub max_spp: u32,
    pub script: Option<VecDeque<Action>>,
    /// A script that has not finished after this long fails.
    pub script_timeout: Duration,
    /// Set when a script step failed or timed out; the process exits non-zero.
    pub failure: Arc<Mutex<Option<String>>>,
}

pub struct Viewer {
    pub(crate) desc: SceneDesc,
    base: PathBuf,
    origin: String,
    pub(crate) backend: Backend,
    pub(crate) gpu: Option<Arc<fogbank::Gpu>>,
    cpu_threads: usize,
    max_spp: u32,
    /// The scene the sessions render (its `desc` is what was built).
    built: Option<Scene>,
    session: Option<Session>,
    /// Split screen: the second estimator and its session.
    pub(crate) split: Option<String>,
    split_session: Option<Session>,
    pub(crate) tone: ToneMapping,
    pub(crate) overlay: Overlay,
    pub(crate) show_help: bool,
    pub(crate) message: String,
    pub(crate) save_image_path: String,
    pub(crate) save_scene_path: String,
    texture: Option<egui::TextureHandle>,
    /// What the texture shows, so a repaint that changes nothing (a mouse
    /// move, a finished render) does not tone-map the image again.
    shown: Option<Shown>,
    script: Option<VecDeque<Action>>,
    script_started: Instant,
    script_timeout: Duration,
    /// Set by a screenshot callback when the file is written.
    screenshot_pending: Option<ScreenshotSlot>,
    failure: Arc<Mutex<Option<String>>>,
    repaint: Option<Arc<dyn Fn() + Send + Sync>>,
}

/// The inputs of the displayed texture.
struct Shown {
    left: Arc<Snapshot>,
    right: Option<Arc<Snapshot>>,
    tone: ToneMapping,
    overlay: Overlay,
}

impl Shown {
    /// Same snapshots (the very same objects, held here so that their
    /// addresses cannot be reused) and the same display settings.
    fn same(&self, o: &Shown) -> bool {
        let right = match (&self.right, &o.right) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        };
        Arc::ptr_eq(&self.left, &o.left)
            && right
            && self.tone == o.tone
            && self.overlay == o.overlay
    }
}

impl Viewer {
    pub fn new(cfg: ViewConfig, ctx: &egui::Context) -> Viewer {
        let c = ctx.clone();
        let tone = cfg.desc.render.tone_mapping();
        let mut v = Viewer {
            desc: cfg.desc,
            base: cfg.base,
            origin: cfg.origin,
            backend: cfg.backend,
            gpu: cfg.gpu,
            cpu_threads: cfg.cpu_threads,
            max_spp: cfg.max_spp,
            built: None,
            session: None,
            split: None,
            split_session: None,
            tone,
            overlay: Overlay::Image,
            show_help: false,
            message: String::new(),
            save_image_path: "fogbank_view.exr".into(),
            save_scene_path: "fogbank_view.toml".into(),
            texture: None,
            shown: None,
            script: cfg.script,
            script_started: Instant::now(),
            script_timeout: cfg.script_timeout,
            screenshot_pending: None,
            failure: cfg.failure,
            repaint: Some(Arc::new(move || c.request_repaint())),
        };
        v.restart();
        v
    }

    /// Builds the scene from `desc` (only the camera, when nothing else
    /// changed: media are not rebuilt) and restarts accumulation.
    pub(crate) fn restart(&mut self) {
        self.stop_sessions();
        let scene = match &self.built {
            Some(old) if same_but_camera(&old.desc, &self.desc) => {
                let mut s = old.clone();
                match self.desc.camera.build() {
                    Ok(cam) => {
                        s.world.camera = cam;
                        s.desc.camera = self.desc.camera.clone();
                        Ok(s)
                    }
                    Err(e) => Err(e.to_string()),
                }
            }
            _ => Scene::build(self.desc.clone(), &self.base).map_err(|e| e.to_string()),
        };
        let scene = match scene {
            Ok(s) => s,
            Err(e) => {
                // Keep showing the last image; say why the change failed.
                self.message = e;
                if let Some(old) = &self.built {
                    self.desc = old.desc.clone();
                }
                return;
            }
        };
        self.message.clear();
        let on_pass = self.repaint.clone().unwrap();
        let split_scene = match self.split.clone() {
            Some(est) => {
                let sets = [format!("integrator.estimator={est}")];
                match self.rebuilt_with(&scene, &sets) {
                    Ok(s) => Some(s),
                    Err(e) => {
                        self.message = format!("split: {e}");
                        None
                    }
                }
            }
            None => None,
        };
        // Equal time: the two halves share the CPU threads (or the GPU).
        let share = if split_scene.is_some() { 2 } else { 1 };
        let backend = match &self.backend {
            Backend::Cpu { .. } => Backend::Cpu {
                threads: (self.cpu_threads / share).max(1),
            },
            b => b.clone(),
        };
        self.session = Some(Session::start(
            scene.clone(),
            backend.clone(),
            self.max_spp,
            on_pass.clone(),
        ));
        self.split_session = split_scene.map(|s| Session::start(s, backend, self.max_spp, on_pass));
        self.built = Some(scene);
    }

    /// `scene` with `sets` applied to its description.
    fn rebuilt_with(&self, scene: &Scene, sets: &[String]) -> Result<Scene, String> {
        let text = toml::to_string(&scene.desc).map_err(|e| e.to_string())?;
        let desc = parse_scene(&text, &self.origin, sets).map_err(|e| e.to_string())?;
        Scene::build(desc, &self.base).map_err(|e| e.to_string())
    }

    fn stop_sessions(&mut self) {
        if let Some(s) = self.session.as_mut() {
            s.stop();
        }
        if let Some(s) = self.split_session.as_mut() {
            s.stop();
        }
    }

    pub(crate) fn snapshot(&self) -> Option<Arc<Snapshot>> {
        self.session.as_ref().and_then(|s| s.snapshot())
    }

    /// Applies one action; returns false while it is still in progress
    /// (waiting for samples or a screenshot), so a script retries it.
    pub(crate) fn act(&mut self, action: &Action, ctx: &egui::Context) -> Result<bool, String> {
        match action {
            Action::WaitSpp(n) => {
                let spp = self.snapshot().map_or(0, |s| s.spp);
                let split_spp = self
                    .split_session
                    .as_ref()
                    .map_or(u32::MAX, |s| s.snapshot().map_or(0, |s| s.spp));
                if let Some(e) = self.session.as_ref().and_then(|s| s.error()) {
                    return Err(e);
                }
                let finished = self.session.as_ref().is_none_or(|s| s.finished());
                return Ok(spp.min(split_spp) >= (*n).min(self.max_spp) || finished);
            }
            Action::Screenshot(path) => return self.screenshot(path, ctx),
            Action::Orbit(yaw, pitch) => orbit::orbit(&mut self.desc.camera, *yaw, *pitch),
            Action::Pan(dx, dy) => orbit::pan(&mut self.desc.camera, *dx, *dy),
            Action::Zoom(f) => orbit::zoom(&mut self.desc.camera, *f),
            Action::Set(sets) => {
                let text = toml::to_string(&self.desc).map_err(|e| e.to_string())?;
                self.desc = parse_scene(&text, &self.origin, sets).map_err(|e| e.to_string())?;
            }
            Action::Key { name, ctrl, shift } => {
                let key = egui::Key::from_name(name).ok_or(format!("unknown key {name}"))?;
                let m = egui::Modifiers {
                    ctrl: *ctrl,
                    command: *ctrl,
                    shift: *shift,
                    ..Default::default()
                };
                self.message.clear();
                self.key(key, m, ctx);
                return if self.message.starts_with("saved") || self.message.is_empty() {
                    Ok(true)
                } else {
                    Err(self.message.clone())
                };
            }
            Action::Overlay(o) => {
                self.overlay = *o;
                return Ok(true);
            }
            Action::Split(s) => self.split = s.clone(),
            Action::Exposure(e) => {
                self.tone.exposure = *e;
                return Ok(true);
            }
            Action::ToneCurve(c) => {
                self.tone.curve = *c;
                return Ok(true);
            }
            Action::SaveImage(p) => {
                self.save_image(p)?;
                return Ok(true);
            }
            Action::SaveScene(p) => {
                self.save_scene(p)?;
                return Ok(true);
            }
            Action::Quit => {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                return Ok(true);
            }
        }
        self.restart();
        if self.message.is_empty() {
            Ok(true)
        } else {
            Err(self.message.clone())
        }
    }

    fn screenshot(&mut self, path: &Path, ctx: &egui::Context) -> Result<bool, String> {
        match self.screenshot_pending.take() {
            None => {
                let slot = Arc::new(Mutex::new(None));
                let (s, p) = (slot.clone(), path.to_path_buf());
                ctx.request_screenshot(move |img| {
                    let rgba: Vec<u8> = img.pixels.iter().flat_map(|c| c.to_array()).collect();
                    let r = image::save_buffer(
                        &p,
                        &rgba,
                        img.size[0] as u32,
                        img.size[1] as u32,
                        image::ColorType::Rgba8,
                    )
                    .map_err(|e| format!("{}: {e}", p.display()));
                    *s.lock().unwrap() = Some(r);
                });
                self.screenshot_pending = Some(slot);
                Ok(false)
            }
            Some(slot) => {
                let done = slot.lock().unwrap().take();
                match done {
                    Some(r) => r.map(|_| true),
                    None => {
                        self.screenshot_pending = Some(slot);
                        Ok(false)
                    }
                }
            }
        }
    }

    /// The accumulated image: EXR (linear, with the `variance` layer that
    /// `compare --metric ztest` reads) or PNG (tone-mapped as shown).
    pub(crate) fn save_image(&mut self, path: &Path) -> Result<(), String> {
        let s = self.snapshot().ok_or("nothing rendered yet")?;
        let r = match path.extension().and_then(|e| e.to_str()) {
            Some("exr") => write_exr(path, s.width, s.height, &s.mean, Some(&s.variance)),
            Some("png") => write_png(path, s.width, s.height, &s.mean, &self.tone),
            _ => Err(format!("{}: save as .exr or .png", path.display())),
        };
        self.message = match &r {
            Ok(()) => format!("saved {} ({} spp)", path.display(), s.spp),
            Err(e) => e.clone(),
        };
        r
    }

    /// The scene as shown, with `render.spp` set to the samples accumulated
    /// so far and the display settings, so that `fogbank render FILE`
    /// reproduces the image (same scene, seed and sample indices).
    pub(crate) fn save_scene(&mut self, path: &Path) -> Result<(), String> {
        let mut desc = self
            .built
            .as_ref()
            .map(|s| s.desc.clone())
            .unwrap_or_else(|| self.desc.clone());
        if let Some(s) = self.snapshot() {
            desc.render.spp = s.spp.max(1);
        }
        desc.render.exposure = self.tone.exposure;
        desc.render.tonemap = self.tone.curve;
        let mut value = toml::Value::try_from(&desc).map_err(|e| e.to_string())?;
        // Relative file names resolve against the saved file's folder.
        let to = path.parent().filter(|p| !p.as_os_str().is_empty());
        fogbank::desc::rebase_paths(&mut value, &self.base, to.unwrap_or(Path::new(".")));
        let text = toml::to_string(&value).map_err(|e| e.to_string())?;
        let header = format!("# Saved by `fogbank view` from {}.\n", self.origin);
        let r =
            std::fs::write(path, header + &text).map_err(|e| format!("{}: {e}", path.display()));
        self.message = match &r {
            Ok(()) => format!("saved {}", path.display()),
            Err(e) => e.clone(),
        };
        r
    }

    /// Plays the script's next step, if any; fails the process on error or
    /// timeout.
    fn run_script(&mut self, ctx: &egui::Context) {
        let Some(step) = self.script.as_ref().and_then(|s| s.front().cloned()) else {
            return;
        };
        if self.script_started.elapsed() > self.script_timeout {
            self.fail(format!("script timed out at {step:?}"), ctx);
            return;
        }
        match self.act(&step, ctx) {
            Ok(true) => {
                self.script.as_mut().unwrap().pop_front();
            }
            Ok(false) => {}
            Err(e) => self.fail(format!("script step {step:?}: {e}"), ctx),
        }
        // Keep frames coming while the script runs (a wait or a screenshot
        // needs another frame to finish).
        ctx.request_repaint_after(Duration::from_millis(20));
    }

    fn fail(&mut self, e: String, ctx: &egui::Context) {
        *self.failure.lock().unwrap() = Some(e);
        self.script = None;
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    fn upload(&mut self, ctx: &egui::Context) -> Option<(egui::TextureId, [usize; 2])> {
        let left = self.snapshot()?;
        let right = self.split_session.as_ref().and_then(|s| s.snapshot());
        let size = [left.width as usize, left.height as usize];
        let now = Shown {
            left,
            right,
            tone: self.tone,
            overlay: self.overlay,
        };
        if let (Some(t), Some(before)) = (&self.texture, &self.shown) {
            if before.same(&now) {
                return Some((t.id(), size));
            }
        }
        let rgba = display::pixels(&now.left, now.right.as_deref(), &self.tone, self.overlay);
        self.shown = Some(now);
        let image = egui::ColorImage::from_rgba_unmultiplied(size, &rgba);
        match &mut self.texture {
            Some(t) => t.set(image, egui::TextureOptions::NEAREST),
            None => {
                self.texture =
                    Some(ctx.load_texture("render", image, egui::TextureOptions::NEAREST))
            }
        }
        self.texture.as_ref().map(|t| (t.id(), size))
    }

    fn image_area(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        let Some((id, size)) = self.upload(&ctx) else {
            ui.centered_and_justified(|ui| ui.label(self.message.clone()));
            return;
        };
        let avail = ui.available_size();
        let scale = (avail.x / size[0] as f32).min(avail.y / size[1] as f32);
        let shown = egui::vec2(size[0] as f32, size[1] as f32) * scale;
        let response = ui
            .centered_and_justified(|ui| {
                ui.add(egui::Image::new((id, shown)).sense(egui::Sense::click_and_drag()))
            })
            .inner;
        let d = response.drag_delta();
        if d != egui::Vec2::ZERO {
            if response.dragged_by(egui::PointerButton::Primary) {
                let _ = self.act(&Action::Orbit(0.4 * d.x, 0.4 * d.y), &ctx);
            } else {
                let h = shown.y.max(1.0);
                let _ = self.act(&Action::Pan(d.x / h, d.y / h), &ctx);
            }
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                let _ = self.act(&Action::Zoom((-scroll * 0.002).exp()), &ctx);
            }
        }
        if let Some(split) = &self.split {
            let est = self
                .built
                .as_ref()
                .map_or("", |s| s.integrator.estimator_name());
            let rect = response.rect;
            let painter = ui.painter();
            let font = egui::FontId::proportional(14.0);
            let color = egui::Color32::WHITE;
            painter.text(
                rect.left_top() + egui::vec2(6.0, 4.0),
                egui::Align2::LEFT_TOP,
                est,
                font.clone(),
                color,
            );
            painter.text(
                rect.right_top() + egui::vec2(-6.0, 4.0),
                egui::Align2::RIGHT_TOP,
                split,
                font,
                color,
            );
        }
    }

    fn status_line(&self, ui: &mut egui::Ui) {
        let text = match self.snapshot() {
            Some(s) => {
                let mut t = format!(
                    "{} · {}×{} · {} spp · {:.1} ms/pass · {:.2} Mrays/s",
                    self.backend.name(),
                    s.width,
                    s.height,
                    s.spp,
                    s.ms_per_pass(),
                    s.mrays_per_s()
                );
                if let Some(r) = self.split_session.as_ref().and_then(|s| s.snapshot()) {
                    t += &format!(" | right: {} spp, {:.1} ms/pass", r.spp, r.ms_per_pass());
                }
                t
            }
            None => "rendering…".into(),
        };
        ui.horizontal(|ui| {
            ui.label(text);
            if let Some(e) = self.session.as_ref().and_then(|s| s.error()) {
                ui.colored_label(egui::Color32::LIGHT_RED, e);
            } else if !self.message.is_empty() {
                ui.label(&self.message);
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                ui.label("H: help");
            });
        });
    }
}

impl Viewer {
    /// The control panel, and what its changes do.
    fn controls(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        let mut state = PanelState {
            desc: &mut self.desc,
            backend: self.backend.name(),
            gpu_available: self.gpu.is_some(),
            tone: self.tone,
            overlay: self.overlay,
            split: self.split.clone(),
            save_image_path: &mut self.save_image_path,
            save_scene_path: &mut self.save_scene_path,
        };
        let out = controls::panel(&mut state, ui);
        let mut restart = out.edited;
        if let Some(b) = out.backend {
            self.backend = match (b.as_str(), &self.gpu) {
                ("gpu", Some(g)) => Backend::Gpu(g.clone()),
                _ => Backend::Cpu {
                    threads: self.cpu_threads,
                },
            };
            restart = true;
        }
        if restart {
            self.restart();
        }
        for a in out.actions {
            if let Err(e) = self.act(&a, ctx) {
                self.message = e;
            }
        }
    }
}

/// Whether two descriptions differ in the camera only.
fn same_but_camera(a: &SceneDesc, b: &SceneDesc) -> bool {
    let mut b = b.clone();
    b.camera = a.camera.clone();
    *a == b
}

impl eframe::App for Viewer {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.run_script(&ctx);
        self.keys(&ctx);
        egui::Panel::bottom("status").show(ui, |ui| self.status_line(ui));
        egui::Panel::left("controls")
            .resizable(true)
            .default_size(270.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls(ui, &ctx));
            });
        egui::CentralPanel::default().show(ui, |ui| self.image_area(ui));
        self.help_window(&ctx);
    }

    fn on_exit(&mut self) {
        self.stop_sessions();
    }
}

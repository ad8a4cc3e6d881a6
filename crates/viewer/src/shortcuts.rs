//! Keyboard shortcuts and the help overlay that lists them (H or F1).

use crate::app::Viewer;
use crate::display::Overlay;
use crate::script::Action;
use eframe::egui;

/// The keyboard and mouse shortcuts, as the help overlay lists them.
pub const SHORTCUTS: [(&str, &str); 14] = [
    ("drag (left)", "orbit about the target"),
    ("drag (right / middle)", "pan"),
    ("wheel, + / −", "zoom"),
    ("arrow keys", "orbit by 10°"),
    ("O", "toggle relative-error overlay"),
    ("E / Shift+E", "exposure +½ / −½ stop"),
    ("T", "next tone curve (linear, ACES, AgX)"),
    ("R", "restart accumulation"),
    ("Ctrl+S", "save image (path in the panel)"),
    ("Ctrl+Shift+S", "save scene (TOML for `fogbank render`)"),
    ("H / F1", "this help"),
    ("Ctrl+Q", "quit"),
    ("panel", "integrator, estimator, medium, light, display"),
    ("split", "two estimators side by side at equal time"),
];

impl Viewer {
    pub(crate) fn keys(&mut self, ctx: &egui::Context) {
        use egui::Key;
        let pressed: Vec<(Key, egui::Modifiers)> = ctx.input(|i| {
            i.events
                .iter()
                .filter_map(|e| match e {
                    egui::Event::Key {
                        key,
                        pressed: true,
                        modifiers,
                        ..
                    } => Some((*key, *modifiers)),
                    _ => None,
                })
                .collect()
        });
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        for (key, m) in pressed {
            self.key(key, m, ctx);
        }
    }

    /// What one key press does (from the keyboard or a script's `key` step).
    pub(crate) fn key(&mut self, key: egui::Key, m: egui::Modifiers, ctx: &egui::Context) {
        use egui::Key;
        {
            let action = match key {
                Key::H | Key::F1 => {
                    self.show_help = !self.show_help;
                    None
                }
                Key::ArrowLeft => Some(Action::Orbit(-10.0, 0.0)),
                Key::ArrowRight => Some(Action::Orbit(10.0, 0.0)),
                Key::ArrowUp => Some(Action::Orbit(0.0, 10.0)),
                Key::ArrowDown => Some(Action::Orbit(0.0, -10.0)),
                Key::Plus | Key::Equals => Some(Action::Zoom(0.9)),
                Key::Minus => Some(Action::Zoom(1.0 / 0.9)),
                Key::O => Some(Action::Overlay(match self.overlay {
                    Overlay::Image => Overlay::RelativeError,
                    Overlay::RelativeError => Overlay::Image,
                })),
                Key::E if m.shift => Some(Action::Exposure(self.tone.exposure - 0.5)),
                Key::E => Some(Action::Exposure(self.tone.exposure + 0.5)),
                Key::T => Some(Action::ToneCurve(self.tone.curve.next())),
                Key::S if m.command && m.shift => {
                    Some(Action::SaveScene(self.save_scene_path.clone().into()))
                }
                Key::S if m.command => Some(Action::SaveImage(self.save_image_path.clone().into())),
                Key::R => {
                    self.restart();
                    None
                }
                Key::Q if m.command => Some(Action::Quit),
                _ => None,
            };
            if let Some(a) = action {
                if let Err(e) = self.act(&a, ctx) {
                    self.message = e;
                }
            }
        }
    }

    /// The shortcut list, centred over the window, while `show_help`.
    pub(crate) fn help_window(&self, ctx: &egui::Context) {
        if self.show_help {
            egui::Window::new("Shortcuts")
                .collapsible(false)
                .resizable(false)
                .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
                .show(ctx, |ui| {
                    egui::Grid::new("keys").striped(true).show(ui, |ui| {
                        for (k, what) in SHORTCUTS {
                            ui.strong(k);
                            ui.label(what);
                            ui.end_row();
                        }
                    });
                });
        }
    }
}

//! Scripted sessions (`fogbank view SCENE --script steps.toml`): the same
//! actions a person takes with mouse and keyboard, read from a file and
//! played in order in the real window, so that tests (and reproducible
//! demos) drive the viewer as a user would.
//!
//! ```toml
//! [[step]]
//! wait_spp = 4                      # until the image has 4 samples per pixel
//! [[step]]
//! screenshot = "shot_0.png"         # the whole window, panels included
//! [[step]]
//! orbit = [30.0, 10.0]              # degrees: yaw, pitch
//! [[step]]
//! set = ["integrator.estimator=track_length"]   # any scene key, as `--set`
//! [[step]]
//! save_image = "view.exr"           # the accumulated image (EXR with variance, or PNG)
//! [[step]]
//! save_scene = "view.toml"          # a scene `fogbank render` reproduces exactly
//! [[step]]
//! quit = true
//! ```
//!
//! Every step has exactly one key: `wait_spp`, `screenshot`, `orbit`,
//! `pan` (`[dx, dy]` in image heights), `zoom` (distance factor), `set`,
//! `key` (a shortcut as typed: `"H"`, `"O"`, `"Ctrl+S"`; see the help overlay),
//! `overlay` (`"image"` or `"relative_error"`), `split` (an estimator
//! name, or `"off"`), `exposure`, `tonemap`, `save_image`, `save_scene`,
//! `quit`.

use crate::display::Overlay;
use fogbank::image::ToneCurve;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Something the viewer does, from a key, a widget or a script step.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    WaitSpp(u32),
    Screenshot(PathBuf),
    Orbit(f32, f32),
    Pan(f32, f32),
    Zoom(f32),
    Set(Vec<String>),
    /// A key press with its modifiers (`Ctrl+S` is `("S", ctrl)`).
    Key {
        name: String,
        ctrl: bool,
        shift: bool,
    },
    Overlay(Overlay),
    /// Split screen against this estimator (None: off).
    Split(Option<String>),
    Exposure(f32),
    ToneCurve(ToneCurve),
    SaveImage(PathBuf),
    SaveScene(PathBuf),
    Quit,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ScriptFile {
    step: Vec<Step>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct Step {
    wait_spp: Option<u32>,
    screenshot: Option<PathBuf>,
    orbit: Option<[f32; 2]>,
    pan: Option<[f32; 2]>,
    zoom: Option<f32>,
    set: Option<Vec<String>>,
    key: Option<String>,
    overlay: Option<String>,
    split: Option<String>,
    exposure: Option<f32>,
    tonemap: Option<String>,
    save_image: Option<PathBuf>,
    save_scene: Option<PathBuf>,
    quit: Option<bool>,
}

impl Step {
    fn action(self, base: &Path) -> Result<Action, String> {
        let rel = |p: PathBuf| if p.is_absolute() { p } else { base.join(p) };
        let mut found = Vec::new();
        if let Some(n) = self.wait_spp {
            found.push(Action::WaitSpp(n));
        }
        if let Some(p) = self.screenshot {
            found.push(Action::Screenshot(rel(p)));
        }
        if let Some([y, p]) = self.orbit {
            found.push(Action::Orbit(y, p));
        }
        if let Some([x, y]) = self.pan {
            found.push(Action::Pan(x, y));
        }
        if let Some(z) = self.zoom {
            if !(z > 0.0 && z.is_finite()) {
                return Err(format!("zoom {z} must be a positive factor"));
            }
            found.push(Action::Zoom(z));
        }
        if let Some(s) = self.set {
            found.push(Action::Set(s));
        }
        if let Some(k) = self.key {
            found.push(parse_key(&k)?);
        }
        if let Some(o) = self.overlay {
            found.push(Action::Overlay(match o.as_str() {
                "image" => Overlay::Image,
                "relative_error" => Overlay::RelativeError,
                _ => return Err(format!("overlay {o:?}: choose image or relative_error")),
            }));
        }
        if let Some(s) = self.split {
            found.push(Action::Split((s != "off").then_some(s)));
        }
        if let Some(e) = self.exposure {
            found.push(Action::Exposure(e));
        }
        if let Some(t) = self.tonemap {
            found.push(Action::ToneCurve(ToneCurve::parse(&t)?));
        }
        if let Some(p) = self.save_image {
            found.push(Action::SaveImage(rel(p)));
        }
        if let Some(p) = self.save_scene {
            found.push(Action::SaveScene(rel(p)));
        }
        if self.quit == Some(true) {
            found.push(Action::Quit);
        }
        match found.len() {
            1 => Ok(found.pop().unwrap()),
            0 => Err("a step needs one action key".into()),
            _ => Err("a step has more than one action key; give each its own [[step]]".into()),
        }
    }
}

/// `"Ctrl+Shift+S"` → the key `S` with both modifiers; the key name is
/// egui's (`H`, `F1`, `ArrowLeft`, `Plus`, …).
fn parse_key(text: &str) -> Result<Action, String> {
    let mut parts: Vec<&str> = text.split('+').map(str::trim).collect();
    let name = parts.pop().unwrap_or_default().to_string();
    let (mut ctrl, mut shift) = (false, false);
    for m in parts {
        match m.to_ascii_lowercase().as_str() {
            "ctrl" | "cmd" => ctrl = true,
            "shift" => shift = true,
            _ => {
                return Err(format!(
                    "key {text:?}: unknown modifier {m:?} (Ctrl, Shift)"
                ))
            }
        }
    }
    if eframe::egui::Key::from_name(&name).is_none() {
        return Err(format!("key {text:?}: unknown key {name:?}"));
    }
    Ok(Action::Key { name, ctrl, shift })
}

/// Reads a script; relative output paths resolve against the script's
/// folder. Errors name the file and the step (1-based).
pub fn load(path: &Path) -> Result<Vec<Action>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse(&text, path.parent().unwrap_or(Path::new(".")))
        .map_err(|e| format!("{}: {e}", path.display()))
}

pub fn parse(text: &str, base: &Path) -> Result<Vec<Action>, String> {
    let file: ScriptFile = toml::from_str(text).map_err(|e| e.to_string())?;
    file.step
        .into_iter()
        .enumerate()
        .map(|(i, s)| s.action(base).map_err(|e| format!("step {}: {e}", i + 1)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_parse_in_order_with_paths_beside_the_script() {
        let a = parse(
            "[[step]]\nwait_spp = 2\n[[step]]\norbit = [30, 5]\n[[step]]\nscreenshot = \"s.png\"\n\
             [[step]]\nkey = \"Ctrl+S\"\n[[step]]\nsplit = \"off\"\n[[step]]\ntonemap = \"agx\"\n[[step]]\nquit = true\n",
            Path::new("/d"),
        )
        .unwrap();
        assert_eq!(
            a,
            [
                Action::WaitSpp(2),
                Action::Orbit(30.0, 5.0),
                Action::Screenshot("/d/s.png".into()),
                Action::Key {
                    name: "S".into(),
                    ctrl: true,
                    shift: false
                },
                Action::Split(None),
                Action::ToneCurve(ToneCurve::Agx),
                Action::Quit
            ]
        );
    }

    #[test]
    fn bad_steps_are_named() {
        let e = parse("[[step]]\nwait_spp = 2\norbit = [1, 2]\n", Path::new(".")).unwrap_err();
        assert!(e.contains("step 1") && e.contains("more than one"), "{e}");
        let e = parse("[[step]]\nwait_spp = 2\n[[step]]\n", Path::new(".")).unwrap_err();
        assert!(e.contains("step 2"), "{e}");
        let e = parse("[[step]]\nspin = 2\n", Path::new(".")).unwrap_err();
        assert!(e.contains("spin"), "{e}");
        let e = parse("[[step]]\nkey = \"Hyper+H\"\n", Path::new(".")).unwrap_err();
        assert!(e.contains("Hyper"), "{e}");
        let e = parse("[[step]]\ntonemap = \"reinhard\"\n", Path::new(".")).unwrap_err();
        assert!(e.contains("reinhard"), "{e}");
    }
}

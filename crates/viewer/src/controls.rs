//! The control panel: backend, integrator and its options, estimator and
//! distance sampler, the first medium's density scale, albedo and HG g, the
//! first light's direction and strength, display settings, the split-screen
//! comparison and saving. Scene edits go through the same keys as `--set`
//! (so an integrator switch drops the old integrator's options as on the
//! command line); sliders apply when released, since each change restarts
//! accumulation.

use crate::display::Overlay;
use crate::script::Action;
use eframe::egui;
use fogbank::desc::{DistanceSampler, LightDesc, Param, SceneDesc, INTEGRATORS};
use fogbank::image::{ToneCurve, ToneMapping};

/// What the panel shows and edits: the scene description in place, the
/// rest read-only (changes come back as [`PanelOutput`]).
pub struct PanelState<'a> {
    pub desc: &'a mut SceneDesc,
    pub backend: &'static str,
    pub gpu_available: bool,
    pub tone: ToneMapping,
    pub overlay: Overlay,
    pub split: Option<String>,
    pub save_image_path: &'a mut String,
    pub save_scene_path: &'a mut String,
}

/// What the user asked for in this frame.
#[derive(Default)]
pub struct PanelOutput {
    pub actions: Vec<Action>,
    /// `desc` was edited in place: rebuild and restart.
    pub edited: bool,
    /// Switch to this backend (`cpu` or `gpu`).
    pub backend: Option<String>,
}

fn estimator_names() -> Vec<&'static str> {
    fogbank::Estimator::all().iter().map(|e| e.name()).collect()
}

/// A combo box of `names`; the chosen one when it changed.
fn choose(ui: &mut egui::Ui, label: &str, current: &str, names: &[&str]) -> Option<String> {
    let mut picked = None;
    egui::ComboBox::from_label(label)
        .selected_text(current)
        .show_ui(ui, |ui| {
            for n in names {
                if ui.selectable_label(*n == current, *n).clicked() && *n != current {
                    picked = Some(n.to_string());
                }
            }
        });
    picked
}

/// A slider whose value is applied when the drag ends (or on a click/key).
fn slider(
    ui: &mut egui::Ui,
    value: &mut f32,
    range: std::ops::RangeInclusive<f32>,
    text: &str,
    log: bool,
) -> bool {
    let r = ui.add(egui::Slider::new(value, range).text(text).logarithmic(log));
    r.drag_stopped() || (r.changed() && !r.dragged())
}

pub fn panel(v: &mut PanelState, ui: &mut egui::Ui) -> PanelOutput {
    let mut actions: Vec<Action> = Vec::new();
    let mut edited = false;
    let mut switch_backend = None;
    ui.heading("fogbank");
    ui.collapsing("Render", |ui| {
        switch_backend = render_section(v, ui, &mut actions);
        let mut seed = v.desc.render.seed as f32;
        if slider(ui, &mut seed, 0.0..=1000.0, "seed", false) {
            v.desc.render.seed = seed as u32;
            edited = true;
        }
    });
    if !v.desc.media.is_empty() {
        ui.collapsing("Medium", |ui| edited |= medium_section(v, ui));
    }
    if let Some(light) = v.desc.lights.iter_mut().find(|l| {
        matches!(
            l,
            LightDesc::Directional { .. } | LightDesc::Point { .. } | LightDesc::Spot { .. }
        )
    }) {
        ui.collapsing("Light", |ui| {
            edited |= light_controls(ui, light);
        });
    }
    ui.collapsing("Display", |ui| display_section(v, ui, &mut actions));
    ui.collapsing("Compare", |ui| compare_section(v, ui, &mut actions));
    ui.collapsing("Save", |ui| save_section(v, ui, &mut actions));
    PanelOutput {
        actions,
        edited,
        backend: switch_backend,
    }
}

/// Backend, integrator, its estimator and distance sampler, and every other
/// parameter of its table as text (Enter applies); returns a backend the
/// user switched to.
fn render_section(v: &PanelState, ui: &mut egui::Ui, actions: &mut Vec<Action>) -> Option<String> {
    let names: Vec<&str> = if v.gpu_available {
        vec!["cpu", "gpu"]
    } else {
        vec!["cpu"]
    };
    let switch_backend = choose(ui, "backend", v.backend, &names);
    let integrators: Vec<&str> = INTEGRATORS.iter().map(|(n, _)| *n).collect();
    let current = v.desc.integrator.name();
    if let Some(t) = choose(ui, "integrator", current, &integrators) {
        actions.push(Action::Set(vec![format!("integrator.type={t}")]));
    }
    let params = INTEGRATORS
        .iter()
        .find(|(n, _)| *n == current)
        .map(|(_, p)| *p)
        .unwrap_or(&[]);
    let has = |k: &str| params.iter().any(|p| p.key == k);
    let table = toml::Value::try_from(&v.desc.integrator).ok();
    let value_of = |k: &str| -> Option<String> {
        let t = table.as_ref()?.get(k)?;
        Some(match t {
            toml::Value::String(s) => s.clone(),
            toml::Value::Table(t) => t
                .get("type")
                .and_then(|x| x.as_str())
                .unwrap_or("")
                .to_string(),
            other => other.to_string(),
        })
    };
    if has("estimator") {
        let est = v.desc.integrator.estimator().name();
        if let Some(e) = choose(ui, "estimator", est, &estimator_names()) {
            actions.push(Action::Set(vec![format!("integrator.estimator={e}")]));
        }
    }
    if has("distance_sampler") {
        let ds = value_of("distance_sampler").unwrap_or_else(|| "delta_tracking".into());
        let names = DistanceSampler::ALL.map(|d| d.name());
        if let Some(d) = choose(ui, "distance sampler", &ds, &names) {
            actions.push(Action::Set(vec![format!(
                "integrator.distance_sampler={d}"
            )]));
        }
    }
    for p in params
        .iter()
        .filter(|p| !matches!(p.key, "estimator" | "distance_sampler" | "type"))
    {
        let shown = value_of(p.key).unwrap_or_else(|| p.default.to_string());
        if let Some(text) = param_field(ui, current, p, shown) {
            actions.push(Action::Set(vec![format!("integrator.{}={text}", p.key)]));
        }
    }
    switch_backend
}

/// One integrator parameter as a text field showing `shown` until edited;
/// the edited text when Enter applies it.
fn param_field(ui: &mut egui::Ui, integrator: &str, p: &Param, shown: String) -> Option<String> {
    let id = ui.make_persistent_id(("param", integrator, p.key));
    let mut text: String = ui.data_mut(|d| d.get_temp::<String>(id)).unwrap_or(shown);
    let r = ui
        .horizontal(|ui| {
            ui.label(p.key).on_hover_text(p.meaning);
            ui.add(egui::TextEdit::singleline(&mut text).desired_width(90.0))
        })
        .inner;
    if r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
        ui.data_mut(|d| d.remove::<String>(id));
        return Some(text);
    }
    if r.changed() {
        ui.data_mut(|d| d.insert_temp(id, text));
    }
    None
}

/// Density scale, albedo and HG g of the first medium (the scale applies
/// to all); true when changed.
fn medium_section(v: &mut PanelState, ui: &mut egui::Ui) -> bool {
    let mut edited = false;
    let m = &mut v.desc.media[0];
    let mut scale = m.sigma_t_scale.max();
    if slider(ui, &mut scale, 0.01..=1000.0, "density scale (σ_t)", true) {
        for m in v.desc.media.iter_mut() {
            m.sigma_t_scale = m.sigma_t_scale.with_max(scale);
        }
        edited = true;
    }
    let m = &mut v.desc.media[0];
    let mut albedo = m.albedo.map_or(1.0, |a| a[0]);
    if slider(ui, &mut albedo, 0.0..=1.0, "albedo", false) {
        m.albedo = Some([albedo; 3]);
        edited = true;
    }
    let mut g = m.phase.g;
    if slider(ui, &mut g, -0.95..=0.95, "HG g", false) {
        m.phase.ty = "hg".into();
        m.phase.g = g;
        edited = true;
    }
    edited
}

/// Exposure, tone curve and the overlay (image or relative error).
fn display_section(v: &PanelState, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
    let mut e = v.tone.exposure;
    if ui
        .add(egui::Slider::new(&mut e, -8.0..=8.0).text("exposure (stops)"))
        .changed()
    {
        actions.push(Action::Exposure(e));
    }
    let names = ToneCurve::NAMES;
    if let Some(c) = choose(ui, "tone curve", v.tone.curve.name(), &names) {
        actions.push(Action::ToneCurve(ToneCurve::parse(&c).unwrap()));
    }
    let mut o = v.overlay;
    ui.radio_value(&mut o, Overlay::Image, "image");
    ui.radio_value(
        &mut o,
        Overlay::RelativeError,
        "relative std. error (0 … 20 %)",
    );
    if o != v.overlay {
        actions.push(Action::Overlay(o));
    }
}

/// The split screen at equal time and the estimator of its right half.
fn compare_section(v: &PanelState, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
    let mut on = v.split.is_some();
    if ui.checkbox(&mut on, "split screen at equal time").changed() {
        actions.push(Action::Split(on.then(|| "track_length".to_string())));
    }
    if let Some(s) = v.split.clone() {
        if let Some(e) = choose(ui, "right half", &s, &estimator_names()) {
            actions.push(Action::Split(Some(e)));
        }
    }
}

/// Where to save the image and the scene.
fn save_section(v: &mut PanelState, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
    ui.text_edit_singleline(v.save_image_path);
    if ui.button("save image (.exr / .png)").clicked() {
        actions.push(Action::SaveImage(v.save_image_path.clone().into()));
    }
    ui.text_edit_singleline(v.save_scene_path);
    if ui.button("save scene (.toml)").clicked() {
        actions.push(Action::SaveScene(v.save_scene_path.clone().into()));
    }
}

/// Direction (azimuth and elevation of where the light comes from) and
/// strength of a directional, point or spot light; true when changed.
fn light_controls(ui: &mut egui::Ui, light: &mut LightDesc) -> bool {
    let mut changed = false;
    let strength = match light {
        LightDesc::Directional {
            direction,
            irradiance,
        } => {
            // `direction` is where light travels; the sliders show where it comes from.
            let d = glam::Vec3::from(*direction).normalize_or(glam::Vec3::NEG_Y);
            let mut elevation = (-d.y).clamp(-1.0, 1.0).asin().to_degrees();
            let mut azimuth = (-d.x).atan2(-d.z).to_degrees();
            let a = slider(ui, &mut azimuth, -180.0..=180.0, "azimuth (°)", false);
            let e = slider(ui, &mut elevation, -89.0..=89.0, "elevation (°)", false);
            if a || e {
                let (az, el) = (azimuth.to_radians(), elevation.to_radians());
                *direction = [-az.sin() * el.cos(), -el.sin(), -az.cos() * el.cos()];
                changed = true;
            }
            irradiance
        }
        LightDesc::Point { intensity, .. } | LightDesc::Spot { intensity, .. } => intensity,
        _ => return false,
    };
    let mut k = strength.iter().cloned().fold(0.0, f32::max);
    let old = k;
    if slider(ui, &mut k, 0.001..=1000.0, "strength", true) && old > 0.0 {
        for c in strength.iter_mut() {
            *c *= k / old;
        }
        changed = true;
    } else if old == 0.0 && k > 0.0 {
        *strength = [k; 3];
        changed = true;
    }
    changed
}

//! `[camera]`, `[render]` and `[integrator]` as Mitsuba's `perspective`
//! sensor (with its `hdrfilm`, box `rfilter` and `independent` sampler) and
//! `volpath` integrator.

use super::notes::Notes;
use super::xml::El;
use fogbank_render::error::SceneError;
use fogbank_render::scene::SceneDesc;
use toml::Value;

/// Mitsuba needs a positive near clip: a camera without one gets this.
const NEAR: f32 = 1e-4;

/// The sensor; `medium` is the id of the medium around the camera.
pub fn sensor(desc: &SceneDesc, medium: Option<&str>, notes: &mut Notes) -> Result<El, SceneError> {
    let c = &desc.camera;
    c.build()?;
    let fov_axis = match c.fov_axis.as_str() {
        "y" => "y",
        _ => "x",
    };
    let mut s = El::plugin("sensor", "perspective")
        .child(El::float("fov", c.fov as f64))
        .child(El::string("fov_axis", fov_axis));
    let near = if c.near_clip > 0.0 {
        c.near_clip
    } else {
        notes.note(format!(
            "camera.near_clip 0: Mitsuba needs a positive near clip, written as {NEAR}"
        ));
        NEAR
    };
    s.push(El::float("near_clip", near as f64));
    match c.far_clip {
        Some(f) => s.push(El::float("far_clip", f as f64)),
        None => s.push(El::float("far_clip", 1e7)),
    }
    s.push(to_world(c.from, c.to, c.up, c.mirror));
    let r = &desc.render;
    let sampler = El::plugin("sampler", "independent")
        .child(El::integer("sample_count", r.spp as i64))
        .child(El::integer("seed", r.seed as i64));
    let film = El::plugin("film", "hdrfilm")
        .child(El::integer("width", c.width as i64))
        .child(El::integer("height", c.height as i64))
        .child(El::plugin("rfilter", "box"));
    s.push(sampler);
    s.push(film);
    if let Some(id) = medium {
        s.push(El::new("ref").attr("name", "medium").attr("id", id));
    }
    render_notes(desc, notes);
    Ok(s)
}

/// The camera's look-at; a mirrored camera (pbrt's left-handed `LookAt`)
/// negates the camera's x axis first, which Mitsuba renders as the mirror
/// image (and fogbank's reader reads back as `mirror = true`).
fn to_world(from: [f32; 3], to: [f32; 3], up: [f32; 3], mirror: bool) -> El {
    let f = |v: [f32; 3]| v.map(|x| x as f64);
    let mut t = El::new("transform").attr("name", "to_world");
    if mirror {
        t.push(El::new("scale").attr("x", "-1"));
    }
    let (o, target) = (f(from), f(to));
    let up = f(up);
    let j = |v: [f64; 3]| v.map(super::xml::num).join(", ");
    t.push(
        El::new("lookat")
            .attr("origin", j(o))
            .attr("target", j(target))
            .attr("up", j(up)),
    );
    t
}

/// `[render]` settings Mitsuba has no counterpart for.
fn render_notes(desc: &SceneDesc, notes: &mut Notes) {
    let r = &desc.render;
    if !r.pixel_jitter {
        notes.note("render.pixel_jitter = false: Mitsuba's samplers always jitter; dropped");
    }
    if r.exposure != 0.0 || r.tonemap != fogbank_image::ToneCurve::Linear {
        notes.note(
            "render.exposure / tonemap: display settings (Mitsuba writes linear EXR); dropped",
        );
    }
    if !r.light_sampler.is_auto() {
        notes.note("render.light_sampler: Mitsuba picks lights its own way; dropped");
    }
    if desc.animation.is_some() {
        notes.note("[animation]: Mitsuba scenes are one frame; frame 0 written");
    }
}

/// The integrator: fogbank's `volpath` as Mitsuba's (fogbank counts
/// scattering vertices, Mitsuba path segments: depth + 1; 100000 and more
/// is unlimited, −1). Other integrators have no Mitsuba counterpart and
/// are refused.
pub fn integrator(desc: &SceneDesc, notes: &mut Notes) -> Result<El, SceneError> {
    let t =
        Value::try_from(&desc.integrator).map_err(|e| SceneError(format!("integrator: {e}")))?;
    let ty = t.get("type").and_then(Value::as_str).unwrap_or("");
    if ty != "volpath" {
        return Err(SceneError(format!(
            "integrator `{ty}`: Mitsuba has no counterpart; only volpath converts (set \
             [integrator] type = \"volpath\" to write the scene for Mitsuba)"
        )));
    }
    let int = |k: &str| t.get(k).and_then(Value::as_integer);
    let depth = int("max_depth").unwrap_or(64);
    let depth = if depth >= 100_000 { -1 } else { depth + 1 };
    let mut e = El::plugin("integrator", "volpath").child(El::integer("max_depth", depth));
    if let Some(rr) = int("rr_depth") {
        e.push(El::integer("rr_depth", rr));
    }
    // fogbank's own sampling choices (set away from their defaults).
    let default =
        toml::from_str::<fogbank_render::integrators::IntegratorDesc>("type = \"volpath\"")
            .ok()
            .and_then(|d| Value::try_from(&d).ok());
    if let (Value::Table(tab), Some(Value::Table(d))) = (&t, default) {
        let own = |k: &&String| !["type", "max_depth", "rr_depth"].contains(&k.as_str());
        for (k, v) in tab.iter().filter(|(k, _)| own(k)) {
            if d.get(k) != Some(v) {
                notes.note(format!(
                    "integrator.{k}: a fogbank sampling choice (the same image in expectation); \
                     Mitsuba chooses its own"
                ));
            }
        }
    }
    Ok(e)
}

//! The rendering options: `Camera`, `Film`, `Sampler`, `PixelFilter`,
//! `Integrator` and `Option` as `[camera]`, `[render]` and `[integrator]`.
//!
//! - Camera `perspective`: `fov` (90°) spans the shorter image axis. pbrt's
//!   camera frame is left-handed (image +x along up × view direction, as
//!   its `LookAt` builds it); fogbank's is right-handed, so a camera whose
//!   world-from-camera transform keeps orientation becomes fogbank's
//!   camera with `mirror = true`, and one that flips it (`Scale -1 1 1`
//!   before `LookAt`) becomes an unmirrored one: either way the image is
//!   pbrt's. `lensradius` must be 0 (a pinhole); `screenwindow` and
//!   `frameaspectratio` are refused; `shutteropen`/`shutterclose` (0, 1)
//!   only give the exposure time (motion, `ActiveTransform`, is refused).
//!   Other camera types are refused.
//! - Film `rgb`: `xresolution` × `yresolution` (1280 × 720); `filename`
//!   is accepted, the output file being the command's; `maxcomponentvalue`
//!   (pbrt's clamp of sample values) is not applied, with a notice. A named
//!   `sensor` (`nikon_d850`, …) is approximated by the CIE 1931 observer
//!   (fogbank's linear sRGB), and an explicit `whitebalance` is not applied,
//!   each with a notice. pbrt's imaging ratio (exposure time · `iso` / 100,
//!   `PixelSensor::Create`) becomes `render.exposure` = log2 of it, with a
//!   notice: fogbank scales PNG output and the viewer by it, not the EXR.
//!   Crop windows are refused.
//! - Sampler `halton`, `sobol`, `zsobol`, `paddedsobol`, `pmj02bn`,
//!   `independent`: `pixelsamples` (16) is `render.spp`; `stratified`:
//!   `xsamples` × `ysamples` (4 × 4). `randomization`, `seed` and `jitter`
//!   are read; fogbank's own sampler draws the samples (same expectation,
//!   different noise; a notice says so).
//! - PixelFilter: fogbank integrates each pixel with a box filter of one
//!   pixel (`box` with radius 0.5, exact); pbrt's default gaussian and any
//!   other filter are approximated by it, with a notice.
//! - Integrator `volpath` (the default): `maxdepth` (5) is fogbank's
//!   volpath `max_depth` (both count scattering events); `regularize` must
//!   be false; `lightsampler` `bvh` (fogbank's is used for emitting
//!   triangles) or `power`. `path` is read as `volpath` when the scene has
//!   no media (pbrt's path ignores media, so with media it is refused).
//!   fogbank's Russian roulette differs from pbrt's: noise only.
//! - Option: `disablepixeljitter` (pixel centres) and `seed`.

use super::interpret::{Entity, Parsed, Placed};
use super::params::ParamList;
use super::warnings::Warnings;
use fogbank_render::error::SceneError;
use glam::{DMat3, DVec3};
use toml::{Table, Value};

fn vec3(v: DVec3) -> Value {
    Value::Array(v.to_array().iter().map(|&x| Value::Float(x)).collect())
}

/// `[camera]` and `[render]` from the camera, film, sampler, filter and
/// options (absent statements take pbrt's defaults).
pub fn camera_and_render(
    p: &Parsed,
    warnings: &mut Warnings,
) -> Result<(Table, Table), SceneError> {
    let mut cam = Table::new();
    let mut render = Table::new();
    let (w, h, iso) = film(p.film.as_ref(), warnings)?;
    cam.insert("width".into(), w.into());
    cam.insert("height".into(), h.into());
    // The shorter axis takes the field of view.
    cam.insert("fov_axis".into(), if w < h { "x" } else { "y" }.into());
    let exposure_time = match &p.camera {
        Some(c) => camera(c, &mut cam)?,
        None => {
            // pbrt's default camera: at the origin looking along +z, +y up.
            cam.insert("from".into(), vec3(DVec3::ZERO));
            cam.insert("to".into(), vec3(DVec3::Z));
            cam.insert("up".into(), vec3(DVec3::Y));
            cam.insert("fov".into(), 90.0.into());
            cam.insert("mirror".into(), true.into());
            1.0
        }
    };
    let at = p
        .film
        .as_ref()
        .map(|f| format!("{}: ", f.loc))
        .unwrap_or_default();
    imaging_ratio(exposure_time * iso / 100.0, &at, &mut render, warnings)?;
    sampler(p.sampler.as_ref(), &mut render, warnings)?;
    filter(p.filter.as_ref(), warnings)?;
    options(&p.options, &mut render)?;
    Ok((cam, render))
}

/// pbrt's `PixelSensor` imaging ratio (exposure time · ISO / 100) as
/// `render.exposure` stops, with a notice: fogbank applies exposure to PNG
/// output and the viewer, not to the linear EXR, which pbrt scales.
fn imaging_ratio(
    r: f64,
    at: &str,
    render: &mut Table,
    warnings: &mut Warnings,
) -> Result<(), SceneError> {
    if !(r.is_finite() && r > 0.0) {
        return Err(SceneError(format!(
            "{at}Film: imaging ratio (exposure time · iso / 100) = {r}: the image would be black or undefined"
        )));
    }
    if r != 1.0 {
        render.insert("exposure".into(), r.log2().into());
        warnings.warn(format!("{at}Film: pbrt's imaging ratio (exposure time · iso / 100) {r} is render.exposure {:.3} stops: PNG output and the viewer are scaled by it, the EXR stays unscaled radiance (pbrt's is scaled)", r.log2()));
    }
    Ok(())
}

/// The camera table; returns pbrt's exposure time (shutter close − open).
fn camera(c: &Placed, cam: &mut Table) -> Result<f64, SceneError> {
    let e = &c.entity;
    if e.ty != "perspective" {
        return Err(e.loc.error(format!(
            "Camera \"{}\" is not supported (perspective)",
            e.ty
        )));
    }
    let ps = &e.params;
    let fov = ps.float("fov", 90.0)?;
    if ps.float("lensradius", 0.0)? != 0.0 {
        return Err(e
            .loc
            .error("Camera \"perspective\": a lens (lensradius > 0) is not supported"));
    }
    ps.float("focaldistance", 1e6)?;
    // Without ActiveTransform (refused) the shutter only sets the exposure.
    let exposure_time = ps.float("shutterclose", 1.0)? - ps.float("shutteropen", 0.0)?;
    ps.finish(&e.what("Camera"))?;
    let m = c.ctm;
    let r = DMat3::from_mat4(m);
    if !(r.transpose() * r).abs_diff_eq(DMat3::IDENTITY, 1e-4) {
        return Err(e.loc.error("Camera: the camera transform scales or shears (only rotations, translations and mirrors)"));
    }
    let from = m.transform_point3(DVec3::ZERO);
    cam.insert("from".into(), vec3(from));
    cam.insert("to".into(), vec3(from + m.transform_vector3(DVec3::Z)));
    cam.insert("up".into(), vec3(m.transform_vector3(DVec3::Y)));
    cam.insert("fov".into(), fov.into());
    if r.determinant() > 0.0 {
        cam.insert("mirror".into(), true.into());
    }
    Ok(exposure_time)
}

/// The resolution and ISO of the film.
fn film(f: Option<&Entity>, warnings: &mut Warnings) -> Result<(i64, i64, f64), SceneError> {
    let Some(f) = f else {
        return Ok((1280, 720, 100.0));
    };
    if f.ty != "rgb" {
        return Err(f
            .loc
            .error(format!("Film \"{}\" is not supported (rgb)", f.ty)));
    }
    let ps = &f.params;
    let (w, h) = (ps.int("xresolution", 1280)?, ps.int("yresolution", 720)?);
    if !(1..=16384).contains(&w) || !(1..=16384).contains(&h) {
        return Err(f
            .loc
            .error(format!("Film: resolution {w}×{h} outside 1..=16384")));
    }
    ps.string("filename")?;
    if let Some(m) = ps.one("float", "maxcomponentvalue")? {
        warnings.warn(format!(
            "{}: Film: fogbank does not clamp samples (pbrt's maxcomponentvalue {m}): no bias, more fireflies",
            f.loc
        ));
    }
    sensor(f, warnings)?;
    let iso = ps.float("iso", 100.0)?;
    ps.finish(&f.what("Film"))?;
    Ok((w, h, iso))
}

/// `sensor` and `whitebalance`, accepted with notices: fogbank renders
/// linear sRGB, which is pbrt's default `cie1931` sensor without white
/// balance.
fn sensor(f: &Entity, warnings: &mut Warnings) -> Result<(), SceneError> {
    let ps = &f.params;
    let name = ps.string("sensor")?.unwrap_or("cie1931");
    // pbrt white-balances named sensors to 6500 K unless told otherwise.
    let default_wb = if name == "cie1931" { 0.0 } else { 6500.0 };
    let wb = ps.float("whitebalance", default_wb)?;
    if name != "cie1931" {
        warnings.warn(format!(
            "{}: Film: the spectral sensor \"{name}\" is approximated by the CIE 1931 observer (fogbank renders linear sRGB)",
            f.loc
        ));
    }
    if ps.has("whitebalance") && wb != 0.0 {
        warnings.warn(format!(
            "{}: Film: white balance to {wb} K is not applied (fogbank renders linear sRGB with D65 white)",
            f.loc
        ));
    }
    Ok(())
}

fn sampler(
    s: Option<&Entity>,
    render: &mut Table,
    warnings: &mut Warnings,
) -> Result<(), SceneError> {
    let spp = match s {
        None => 16,
        Some(s) => {
            let ps = &s.params;
            let n = match s.ty.as_str() {
                "halton" | "sobol" | "zsobol" | "paddedsobol" | "pmj02bn" | "independent" => {
                    ps.int("pixelsamples", 16)?
                }
                // pbrt's stratified sampler takes xsamples × ysamples.
                "stratified" => {
                    ps.bool("jitter", true)?;
                    ps.int("xsamples", 4)? * ps.int("ysamples", 4)?
                }
                other => return Err(s.loc.error(format!("Sampler \"{other}\" is unknown"))),
            };
            // Randomisation and seeds only change which noise pbrt's
            // samples have; fogbank's sampler draws its own.
            ps.string("randomization")?;
            ps.int("seed", 0)?;
            ps.finish(&s.what("Sampler"))?;
            warnings.warn(format!(
                "{}: Sampler \"{}\": fogbank's own sampler draws the {n} samples per pixel (same expectation, different noise)",
                s.loc, s.ty
            ));
            n
        }
    };
    if !(1..=1 << 24).contains(&spp) {
        return Err(SceneError(format!(
            "Sampler: pixelsamples {spp} outside 1..=2^24"
        )));
    }
    render.insert("spp".into(), spp.into());
    Ok(())
}

fn filter(f: Option<&Entity>, warnings: &mut Warnings) -> Result<(), SceneError> {
    let Some(f) = f else {
        warnings.warn(
            "pbrt's default gaussian pixel filter is approximated by fogbank's one-pixel box",
        );
        return Ok(());
    };
    let exact = f.ty == "box" && {
        let r = f.params.nums("float", "xradius").unwrap_or(&[0.5]) == [0.5];
        r && f.params.nums("float", "yradius").unwrap_or(&[0.5]) == [0.5]
    };
    if !exact {
        f.params.mark_all_used();
        warnings.warn(format!(
            "{}: PixelFilter \"{}\" is approximated by fogbank's one-pixel box",
            f.loc, f.ty
        ));
    }
    f.params.finish(&f.what("PixelFilter"))
}

fn options(o: &ParamList, render: &mut Table) -> Result<(), SceneError> {
    if o.bool("disablepixeljitter", false)? {
        render.insert("pixel_jitter".into(), false.into());
    }
    if let Some(s) = o.one("integer", "seed")? {
        if !(0.0..=u32::MAX as f64).contains(&s) {
            return Err(SceneError(format!("Option seed {s} outside 0..=2^32-1")));
        }
        render.insert("seed".into(), (s as i64).into());
    }
    o.finish("Option")
}

/// `[integrator]` (and `render.light_sampler`); `has_media`: whether the
/// scene has participating media (pbrt's `path` ignores them).
pub fn integrator(
    i: Option<&Entity>,
    has_media: bool,
    render: &mut Table,
) -> Result<Table, SceneError> {
    let mut t = Table::new();
    t.insert("type".into(), "volpath".into());
    let Some(i) = i else {
        t.insert("max_depth".into(), 5.into());
        return Ok(t);
    };
    match i.ty.as_str() {
        "volpath" => {}
        "path" if !has_media => {}
        "path" => return Err(i.loc.error("Integrator \"path\" ignores this scene's media in pbrt; fogbank renders media (use volpath)")),
        other => return Err(i.loc.error(format!("Integrator \"{other}\" is not supported (volpath, path)"))),
    }
    let ps = &i.params;
    let depth = ps.int("maxdepth", 5)?;
    if !(1..=100_000).contains(&depth) {
        return Err(i
            .loc
            .error(format!("Integrator: maxdepth {depth} outside 1..=100000")));
    }
    t.insert("max_depth".into(), depth.into());
    if ps.bool("regularize", false)? {
        return Err(i.loc.error("Integrator: regularize is not supported"));
    }
    match ps.string("lightsampler")? {
        None => {}
        Some(s @ ("bvh" | "power")) => {
            render.insert("light_sampler".into(), s.into());
        }
        Some(other) => {
            return Err(i.loc.error(format!(
                "Integrator: lightsampler \"{other}\" is not supported (bvh, power)"
            )))
        }
    }
    ps.finish(&i.what("Integrator"))?;
    Ok(t)
}

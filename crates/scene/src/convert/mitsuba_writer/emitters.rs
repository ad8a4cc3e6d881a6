//! `[[lights]]` as Mitsuba emitters: `constant`, `envmap` (its `rotate` as
//! the `to_world` rotation), `point`, `directional`, `spot` (a look-at from
//! its position along its direction). The gradient `sky` has no Mitsuba
//! counterpart: it is baked into the latitude–longitude map fogbank builds
//! of it, written beside the XML as `STEM_lightI.exr`, an `envmap` (noted:
//! Mitsuba looks it up bilinearly). A smoothstep spot falloff is written as
//! Mitsuba's linear one, with a note.

use super::notes::Notes;
use super::xml::{num, El};
use fogbank_image::image_io::write_exr;
use fogbank_render::error::SceneError;
use fogbank_render::lights::sky::sky_pixels;
use fogbank_render::lights::{LightDesc, SpotCurve};
use std::path::Path;

fn xyz(v: [f32; 3]) -> [f64; 3] {
    v.map(|x| x as f64)
}

/// Light `i` as an `<emitter>`; files it needs go to `dir` as
/// `STEM_lightI.exr`.
pub fn emitter(
    l: &LightDesc,
    i: usize,
    (dir, stem): (&Path, &str),
    notes: &mut Notes,
) -> Result<El, SceneError> {
    let key = format!("lights.{i}");
    Ok(match l {
        LightDesc::Constant { radiance } => {
            El::plugin("emitter", "constant").child(El::rgb("radiance", *radiance))
        }
        LightDesc::Envmap {
            file,
            scale,
            rotate,
            filter,
        } => {
            if filter.as_deref() != Some("bilinear") {
                notes.note(format!(
                    "{key}.filter: Mitsuba looks its environment map up bilinearly (fogbank's \
                     default is nearest)"
                ));
            }
            let mut e = El::plugin("emitter", "envmap")
                .child(El::string("filename", file))
                .child(El::float("scale", *scale as f64));
            if let Some([x, y, z, deg]) = rotate {
                let r = El::new("rotate")
                    .attr("x", num(*x as f64))
                    .attr("y", num(*y as f64))
                    .attr("z", num(*z as f64))
                    .attr("angle", num(*deg as f64));
                e.push(El::new("transform").attr("name", "to_world").child(r));
            }
            e
        }
        LightDesc::Point {
            position,
            intensity,
        } => El::plugin("emitter", "point")
            .child(El::xyz("point", "position", xyz(*position)))
            .child(El::rgb("intensity", *intensity)),
        LightDesc::Directional {
            direction,
            irradiance,
        } => El::plugin("emitter", "directional")
            .child(El::xyz("vector", "direction", xyz(*direction)))
            .child(El::rgb("irradiance", *irradiance)),
        LightDesc::Sky {
            zenith,
            horizon,
            ground,
            scale,
        } => {
            let name = format!("{stem}_light{i}.exr");
            let (w, h, rgb) = sky_pixels(*zenith, *horizon, *ground);
            write_exr(&dir.join(&name), w as u32, h as u32, &rgb, None)
                .map_err(|e| SceneError(format!("{}: {e}", dir.join(&name).display())))?;
            notes.note(format!(
                "{key}: the gradient sky baked into {name} ({w}×{h}), an envmap Mitsuba looks up \
                 bilinearly"
            ));
            El::plugin("emitter", "envmap")
                .child(El::string("filename", &name))
                .child(El::float("scale", *scale as f64))
        }
        LightDesc::Spot {
            position,
            direction,
            intensity,
            cone_angle,
            falloff_start,
            curve,
        } => {
            if *curve != SpotCurve::Linear {
                notes.note(format!(
                    "{key}.curve: Mitsuba's spot falls off linearly in angle; the smoothstep \
                     falloff is written as linear"
                ));
            }
            El::plugin("emitter", "spot")
                .child(look_along(*position, *direction))
                .child(El::rgb("intensity", *intensity))
                .child(El::float("cutoff_angle", *cone_angle as f64))
                .child(El::float("beam_width", *falloff_start as f64))
        }
    })
}

/// A `to_world` whose origin is `p` and +z is `d`.
fn look_along(p: [f32; 3], d: [f32; 3]) -> El {
    let target = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
    let dv = glam::Vec3::from(d).normalize_or_zero();
    let up = if dv.y.abs() > 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let j = |v: [f32; 3]| v.map(|x| num(x as f64)).join(", ");
    El::new("transform").attr("name", "to_world").child(
        El::new("lookat")
            .attr("origin", j(p))
            .attr("target", j(target))
            .attr("up", j(up)),
    )
}

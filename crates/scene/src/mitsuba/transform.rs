//! `<transform>`: `translate`, `rotate`, `scale`, `matrix` and `lookat`,
//! each applied after the ones before it (Mitsuba's order).

use super::values::{numbers, xyz};
use super::xml::Element;
use fogbank_render::error::SceneError;
use glam::{DMat4, DVec3};

pub fn read_transform(t: &Element) -> Result<DMat4, SceneError> {
    let mut m = DMat4::IDENTITY;
    for c in &t.children {
        let step = match c.tag.as_str() {
            "translate" => DMat4::from_translation(DVec3::from(xyz(c, 0.0)?)),
            "scale" => DMat4::from_scale(DVec3::from(xyz(c, 1.0)?)),
            "rotate" => {
                let axis = DVec3::from(xyz(c, 0.0)?);
                let angle = c
                    .attr("angle")
                    .and_then(|a| a.trim().parse::<f64>().ok())
                    .ok_or_else(|| c.error("needs a numeric `angle` (degrees)"))?;
                let axis = axis
                    .try_normalize()
                    .ok_or_else(|| c.error("the rotation axis is zero"))?;
                DMat4::from_axis_angle(axis, angle.to_radians())
            }
            "matrix" => {
                let v = c.attr("value").ok_or_else(|| c.error("needs `value`"))?;
                let xs = numbers(v).map_err(|e| c.error(e))?;
                let rows: [f64; 16] = match xs.len() {
                    16 => xs.try_into().expect("16 numbers"),
                    9 => {
                        let x = &xs;
                        [
                            x[0], x[1], x[2], 0.0, x[3], x[4], x[5], 0.0, x[6], x[7], x[8], 0.0,
                            0.0, 0.0, 0.0, 1.0,
                        ]
                    }
                    n => return Err(c.error(format!("{n} numbers (need 16, or 9)"))),
                };
                if rows[12..] != [0.0, 0.0, 0.0, 1.0] {
                    return Err(c.error("a projective matrix (last row not 0 0 0 1)"));
                }
                DMat4::from_cols_array(&rows).transpose()
            }
            "lookat" => lookat(c)?,
            _ => {
                return Err(
                    c.error("is not a transform step (translate, rotate, scale, matrix, lookat)")
                )
            }
        };
        m = step * m;
    }
    if !m.is_finite() {
        return Err(t.error("the transform is not finite"));
    }
    Ok(m)
}

/// Mitsuba's `lookat`: camera space +z toward `target`, +y up, +x left.
fn lookat(c: &Element) -> Result<DMat4, SceneError> {
    let get = |k: &str| -> Result<DVec3, SceneError> {
        let v = c.attr(k).ok_or_else(|| c.error(format!("needs `{k}`")))?;
        match numbers(v).map_err(|e| c.error(e))?.as_slice() {
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(c.error(format!("{k} = `{v}` is not three numbers"))),
        }
    };
    let origin = get("origin")?;
    let dir = (get("target")? - origin)
        .try_normalize()
        .ok_or_else(|| c.error("origin and target coincide"))?;
    let up = c
        .attr("up")
        .map(|_| get("up"))
        .transpose()?
        .unwrap_or(DVec3::Y);
    let left = up
        .cross(dir)
        .try_normalize()
        .ok_or_else(|| c.error("`up` is parallel to the view direction"))?;
    let new_up = dir.cross(left);
    Ok(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}

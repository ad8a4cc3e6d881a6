//! Numbers and vectors written in attribute values.

use super::xml::Element;
use crate::error::SceneError;

/// Comma- or space-separated numbers.
pub fn numbers(v: &str) -> Result<Vec<f64>, String> {
    v.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("`{s}` is not a finite number"))
        })
        .collect()
}

/// A vector from `value="x, y, z"` (one value: all three) or the `x`, `y`,
/// `z` attributes (missing ones are `fill`).
pub fn xyz(c: &Element, fill: f64) -> Result<[f64; 3], SceneError> {
    if let Some(v) = c.attr("value") {
        return match numbers(v).map_err(|e| c.error(e))?.as_slice() {
            [x] => Ok([*x; 3]),
            [x, y, z] => Ok([*x, *y, *z]),
            _ => Err(c.error(format!("`{v}` is not one value or three"))),
        };
    }
    let mut out = [fill; 3];
    for (i, k) in ["x", "y", "z"].iter().enumerate() {
        if let Some(v) = c.attr(k) {
            out[i] = v
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| c.error(format!("{k} = `{v}` is not a finite number")))?;
        }
    }
    Ok(out)
}

//! Numbers and vectors written in attribute values.

use super::xml::Element;
use fogbank_image::spectrum::{constant_spectrum_to_srgb, spectrum_to_srgb, SpectrumUse};
use fogbank_render::error::SceneError;

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

/// A `<spectrum>` value as linear sRGB: one number (a constant) or
/// wavelength:value pairs (`"400:0.1, 500:0.3"`, nm), converted as
/// Mitsuba's RGB variants do for `usage`.
pub fn spectrum(v: &str, usage: SpectrumUse) -> Result<[f64; 3], String> {
    let tokens: Vec<&str> = v
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .collect();
    if let [one] = tokens.as_slice() {
        if !one.contains(':') {
            let x = numbers(one)?[0];
            return Ok(constant_spectrum_to_srgb(x, usage));
        }
    }
    let (mut wavelengths, mut values) = (Vec::new(), Vec::new());
    for t in &tokens {
        let pair: Vec<&str> = t.split(':').collect();
        let [w, x] = pair.as_slice() else {
            return Err(format!(
                "`{t}` is not a wavelength:value pair (a spectrum is one number or pairs like \"400:0.1, 700:0.9\")"
            ));
        };
        wavelengths.push(numbers(w)?.first().copied().ok_or("empty wavelength")?);
        values.push(numbers(x)?.first().copied().ok_or("empty value")?);
    }
    spectrum_to_srgb(&wavelengths, &values, usage)
}

//! pbrt-v4's spectrum parameters as fogbank's linear-sRGB triples.
//!
//! - `rgb`: as is (fogbank renders in linear sRGB); negative components
//!   are errors, and a reflectance above 1 is one, as in pbrt.
//! - `blackbody T`: Planck's spectrum normalised to peak 1, in linear sRGB.
//! - `spectrum [λ v …]`: piecewise linear, integrated against the CIE
//!   curves ([`fogbank_image::spectrum`]).
//! - On lights ([`Role::Illuminant`]) pbrt divides the light's scale by
//!   the spectrum's photometric value; for `rgb` only the colour space's
//!   illuminant counts, so an `rgb` radiance renders as that rgb, while a
//!   blackbody or sampled spectrum is normalised to luminance 1.
//! - Named spectra (`"metal-Cu-eta"`, `"glass-BK7"`, …) are errors here;
//!   the conductor reads the named metals itself.

use super::params::{ParamList, Values};
use fogbank_image::spectrum::{spectrum_to_srgb, SpectrumUse};
use fogbank_render::error::SceneError;
use fogbank_render::world::blackbody::blackbody_rgb;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A reflectance or albedo: components in [0, 1].
    Reflectance,
    /// σ, η and other non-negative quantities.
    Unbounded,
    /// Emitted radiance, intensity or irradiance (normalised as pbrt does).
    Illuminant,
}

/// Linear sRGB luminance.
pub fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The spectrum parameter `name` (types `rgb`, `blackbody`, `spectrum`)
/// as linear sRGB.
pub fn spectrum(
    params: &ParamList,
    name: &str,
    role: Role,
) -> Result<Option<[f64; 3]>, SceneError> {
    let Some(p) = params.lookup(name, &["rgb", "blackbody", "spectrum"]) else {
        return Ok(None);
    };
    let nums = match &p.values {
        Values::Nums(v) => v.as_slice(),
        Values::Strs(s) => {
            return Err(p.error(format!(
                "the named spectrum \"{}\" is not supported here; give its rgb",
                s[0]
            )))
        }
        Values::Bools(_) => return Err(p.error("is not a spectrum")),
    };
    let c = match (p.ty.as_str(), nums) {
        ("rgb", [r, g, b]) => [*r, *g, *b],
        ("blackbody", [t]) => {
            let c = blackbody_rgb(*t as f32);
            let c = [c.x as f64, c.y as f64, c.z as f64];
            return normalise(c, role).map(Some).map_err(|m| p.error(m));
        }
        // A constant sampled spectrum is that constant (the CIE tables'
        // rounding would tint it slightly).
        ("spectrum", v) if role != Role::Illuminant && v.chunks(2).all(|c| c[1] == v[1]) => {
            [v[1]; 3]
        }
        ("spectrum", v) => {
            let (wl, val): (Vec<f64>, Vec<f64>) = v.chunks(2).map(|c| (c[0], c[1])).unzip();
            let usage = match role {
                Role::Reflectance => SpectrumUse::Bounded,
                Role::Unbounded => SpectrumUse::Unbounded,
                Role::Illuminant => SpectrumUse::Emitter,
            };
            let c = spectrum_to_srgb(&wl, &val, usage).map_err(|m| p.error(m))?;
            return normalise(c, role).map(Some).map_err(|m| p.error(m));
        }
        _ => return Err(p.error("needs one value (three for rgb)")),
    };
    if c.iter().any(|&x| x < 0.0) {
        return Err(p.error("negative components"));
    }
    if role == Role::Reflectance && c.iter().any(|&x| x > 1.0) {
        return Err(p.error("a reflectance above 1"));
    }
    Ok(Some(c))
}

/// A non-RGB spectrum on a light is scaled to luminance 1 (pbrt divides
/// the light's scale by its photometric value).
fn normalise(c: [f64; 3], role: Role) -> Result<[f64; 3], String> {
    if role != Role::Illuminant {
        return Ok(c);
    }
    let y = luminance(c);
    if y > 0.0 {
        Ok(c.map(|x| x / y))
    } else {
        Err("an emission spectrum with no luminance".into())
    }
}

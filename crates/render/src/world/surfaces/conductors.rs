//! A conductor's complex index of refraction (η, k), as Mitsuba 3 takes it:
//! given as `eta` and `k`, or named by `material` (its measured metals,
//! [`CONDUCTORS`], as its RGB variants see them), or neither: Mitsuba's
//! `material = "none"`, a perfect mirror (η 0, k 1).

pub use super::conductor_table::CONDUCTORS;
use crate::error::SceneError;

/// (η, k) of the conductor `name`.
pub fn conductor(name: &str) -> Option<([f32; 3], [f32; 3])> {
    CONDUCTORS.iter().find(|c| c.0 == name).map(|c| (c.1, c.2))
}

/// The (η, k) of a `conductor` or `roughconductor` table at `key`.
pub fn complex_ior(
    eta: Option<[f32; 3]>,
    k: Option<[f32; 3]>,
    material: Option<&str>,
    key: &str,
) -> Result<([f32; 3], [f32; 3]), SceneError> {
    match material {
        None | Some("none") => Ok((eta.unwrap_or([0.0; 3]), k.unwrap_or([1.0; 3]))),
        Some(_) if eta.is_some() || k.is_some() => Err(SceneError(format!(
            "{key}: give either eta and k or a material, not both (as Mitsuba)"
        ))),
        Some(m) => conductor(m).ok_or_else(|| {
            let names: Vec<&str> = CONDUCTORS.iter().map(|c| c.0).collect();
            SceneError(format!(
                "{key}: `{m}` is not one of Mitsuba's conductors ({})",
                names.join(", ")
            ))
        }),
    }
}

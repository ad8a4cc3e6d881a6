//! Delta tracking that also reports the ratio-tracking weight of its own
//! null collisions, for the MIS of Miller et al. 2019 as Peters 2025 §6.2
//! reduces it: "For free-flight sampling, T_rt(t1) reuses the null-scattering
//! events of delta tracking", T_rt(t) = Π_{j<k} (1 − μ(t'_j)/μ̂(t'_j)).
//!
//! The tentative collisions are those of [`super::delta_tracking::track`]
//! (the super-voxel maximum as rate), the process of [`crate::ratio_tracking`]
//! too, so ratio tracking
//! along `[t0, t]` for another distance sample describes the same null path
//! space (Miller et al.'s pdfs then share every factor but the last).

use super::delta_tracking::track;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::VolumeAccess;

/// A delta-tracking sample with its null-collision record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackedFreeFlight {
    /// Real collision, `None` when the walk left `[t0, t1]`.
    pub t: Option<f32>,
    /// σ_t read at the real collision (0 on escape).
    pub sigma_t: f32,
    /// Π (1 − μ/μ̂) over the null collisions before `t` (over all of them
    /// on escape): the ratio-tracking estimate T_rt(t).
    pub ratio: f32,
    pub lookups: u32,
}

pub fn sample<V: VolumeAccess>(v: &V, seg: &RaySegment, rng: &mut Pcg32) -> TrackedFreeFlight {
    let mut lookups = 0;
    let mut ratio = 1.0;
    let hit = track(v, seg, rng, &mut lookups, |sigma_t, sigma_maj| {
        ratio *= 1.0 - sigma_t / sigma_maj;
    });
    TrackedFreeFlight {
        t: hit.map(|(t, _)| t),
        sigma_t: hit.map_or(0.0, |(_, s)| s),
        ratio,
        lookups,
    }
}

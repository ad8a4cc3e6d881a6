//! Delta tracking (Woodcock; Peters 2025 §2.1) over the super-voxel majorant
//! grid: tentative collisions at rate σ̄, each real with probability σ_t/σ̄.
//! The one loop behind [`sample`], [`super::delta_tracking_ratio`] and the
//! track-length estimator.

use super::FreeFlight;
use crate::null_collisions::{walk, Tracking};
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{SuperVoxel, VolumeAccess};

/// The first real collision `(t, σ_t(t))` in `[t0, t1]`, or `None`;
/// `on_null(σ_t, σ_maj)` sees every null collision before it.
#[inline(always)]
pub fn track<V: VolumeAccess>(
    v: &V,
    seg: &RaySegment,
    rng: &mut Pcg32,
    lookups: &mut u32,
    mut on_null: impl FnMut(f32, f32),
) -> Option<(f32, f32)> {
    let mut hit = None;
    walk(
        v,
        seg,
        rng,
        lookups,
        Tracking {
            draws: 1,
            rate: |s: &SuperVoxel, _| (s.max, 0.0),
            collide: |t, sigma_t, sigma_maj, _, rng: &mut Pcg32| {
                if rng.next_f32() * sigma_maj < sigma_t {
                    hit = Some((t, sigma_t));
                    false
                } else {
                    on_null(sigma_t, sigma_maj);
                    true
                }
            },
        },
    );
    hit
}

pub fn sample<V: VolumeAccess>(v: &V, seg: &RaySegment, rng: &mut Pcg32) -> FreeFlight {
    let mut lookups = 0;
    let hit = track(v, seg, rng, &mut lookups, |_, _| {});
    FreeFlight {
        t: hit.map(|(t, _)| t),
        lookups,
    }
}

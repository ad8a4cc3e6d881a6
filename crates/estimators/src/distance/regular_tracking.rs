//! Regular tracking (Szirmay-Kalos et al. 2010; Peters 2025 §2.1): exact
//! free-flight sampling for the nearest-filtered grid by walking voxels until
//! the optical depth reaches −ln(1 − u), then inverting linearly inside the
//! voxel. Exact for `Filter::Nearest`; for trilinear media it samples the
//! nearest-filtered field.

use super::TrackedFlight;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::{Dda, GridView, Occupied, Voxel, ZERO_NEAREST};

/// A free flight (its [`TrackedFlight::free_flight`]) with σ_t at the collision and the optical depth up to it
/// (Lin et al. 2021 Eq. 27–28: p(t) = T*(t)·σ_t*(t) in closed form).
pub fn sample_tracked<T: Voxel>(
    v: &GridView<'_, T>,
    seg: &RaySegment,
    rng: &mut Pcg32,
) -> TrackedFlight {
    let (ray, t0, t1) = (&seg.ray, seg.t0, seg.t1);
    let target = -(1.0 - rng.next_f32() as f64).ln();
    let mut tau = 0.0f64;
    let mut lookups = 0;
    // Zero super-voxels hold no collision and add nothing to τ ([`Occupied`]).
    for (ta, tb) in Occupied::new(v.supervoxels, ZERO_NEAREST, ray, t0, t1) {
        for s in Dda::new(ray, 1.0, v.grid.dims(), ta, tb) {
            lookups += 1;
            let s_voxel = v.grid.fetch(s.cell[0], s.cell[1], s.cell[2]);
            let sigma_t = v.scale as f64 * v.classify(s_voxel) as f64;
            let d = sigma_t * (s.t1 - s.t0) as f64;
            if tau + d >= target && sigma_t > 0.0 {
                let t = s.t0 as f64 + (target - tau) / sigma_t;
                return TrackedFlight {
                    t: Some((t as f32).clamp(s.t0, s.t1)),
                    sigma_t,
                    tau: target,
                    lookups,
                };
            }
            tau += d;
        }
    }
    TrackedFlight {
        t: None,
        sigma_t: 0.0,
        tau,
        lookups,
    }
}

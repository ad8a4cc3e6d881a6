//! Track-length estimator (Peters 2025 §2.2): delta tracking over the
//! super-voxel majorant grid, returning 1 if no real collision happens before
//! the end of the segment and 0 otherwise. Unbiased, variance (1 − T)T.

use crate::distance::delta_tracking;
use crate::Estimate;
use fogbank_math::{Pcg32, RaySegment};
use fogbank_volume::VolumeAccess;

pub fn transmittance<V: VolumeAccess>(v: &V, seg: &RaySegment, rng: &mut Pcg32) -> Estimate {
    let f = delta_tracking::sample(v, seg, rng);
    Estimate {
        transmittance: if f.t.is_none() { 1.0 } else { 0.0 },
        lookups: f.lookups,
    }
}

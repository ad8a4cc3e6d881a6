//! One pin (Hansen 2025 §3.1, §3.7, Table 3.1): the line through a point of
//! the unit cube with a direction, cut into 32 equal intervals along its
//! chord, stored as the ratio bitmask Ĩ (Eq. 3.5: bit of interval i set
//! with probability (1 − t_i)/(1 − t_min)) and t_min = min_i t_i, 8 bytes.
//! Interval i sits at bit 31 − i, so the most significant bit is the
//! chord's start; the chord runs towards +z (a line has no sign).

use crate::lookup::sigma_t_at;
use fogbank_math::{Pcg32, Ray, Vec3};
use fogbank_volume::VolumeAccess;
use glam::Mat3;

/// Intervals per pin: one bit each of a `u32`.
pub const INTERVALS: usize = 32;

/// A pin record: Ĩ and t_min.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pin {
    /// Ĩ, the ratio bitmask: interval i at bit 31 − i.
    pub mask: u32,
    /// min_i t_i; 1 means no interval attenuates (and then `mask` = 0).
    pub t_min: f32,
}

impl Pin {
    /// No attenuation anywhere: no collision, T = 1.
    pub const CLEAR: Pin = Pin {
        mask: 0,
        t_min: 1.0,
    };

    /// Hansen 2025 Eq. 3.5 (§3.7): one ratio bitmask for interval
    /// transmittances `t`. With t_min = 1 the ratio is 0/0; every interval
    /// is then clear, so the pin is [`Pin::CLEAR`] (no collision, T = 1).
    pub fn from_transmittances(t: &[f64; INTERVALS], rng: &mut Pcg32) -> Pin {
        let t_min = t.iter().copied().fold(1.0f64, f64::min).max(0.0);
        if t_min >= 1.0 {
            return Pin::CLEAR;
        }
        let mut mask = 0u32;
        for (i, &ti) in t.iter().enumerate() {
            let p = (1.0 - ti.clamp(0.0, 1.0)) / (1.0 - t_min);
            // One f32 draw per bit, as the GPU's gather kernel draws.
            if (rng.next_f32() as f64) < p {
                mask |= 1 << (31 - i);
            }
        }
        Pin {
            mask,
            t_min: t_min as f32,
        }
    }

    /// Traces the pin through `point` (unit cube) along `direction`: the
    /// interval transmittances by jittered ray marching at `step` (in unit-
    /// cube edges, the thesis's 0.01), kept for the second pass so that no
    /// ratio exceeds 1 (the thesis marches twice with fresh jitter).
    pub fn trace<V: VolumeAccess>(
        v: &V,
        cube: &UnitCube,
        point: Vec3,
        direction: Vec3,
        step: f32,
        rng: &mut Pcg32,
    ) -> Pin {
        match cube.chord(point, direction) {
            Some((start, end)) => {
                let t = interval_transmittances(v, cube, start, end, step, rng);
                Pin::from_transmittances(&t, rng)
            }
            None => Pin::CLEAR,
        }
    }
}

/// The medium's unit cube: local point u ↦ index point u ⊙ dims, and world
/// lengths of local vectors (through the index-to-world map's linear part).
#[derive(Clone, Copy, Debug)]
pub struct UnitCube {
    pub dims: Vec3,
    /// Local (unit-cube) vector → world vector.
    pub to_world: Mat3,
}

impl UnitCube {
    pub fn new(dims: [u32; 3], index_to_world: Mat3) -> UnitCube {
        let dims = Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
        UnitCube {
            dims,
            to_world: index_to_world * Mat3::from_diagonal(dims),
        }
    }

    /// The chord of the line through `point` with `direction` (either
    /// sign): its ends in the unit cube, ordered towards +z (§3.10; ties in
    /// z towards +y, then +x, so every line has one orientation).
    pub fn chord(&self, point: Vec3, direction: Vec3) -> Option<(Vec3, Vec3)> {
        let d = canonical(direction);
        if d.length_squared().is_nan() || d.length_squared() <= 0.0 {
            return None;
        }
        let p = point.clamp(Vec3::ZERO, Vec3::ONE);
        let line = Ray::new(p, d);
        let (a, b) = fogbank_math::Aabb::new(Vec3::ZERO, Vec3::ONE).intersect(
            &line,
            f32::NEG_INFINITY,
            f32::INFINITY,
        )?;
        (b > a).then(|| (line.at(a), line.at(b)))
    }
}

/// `d` or −`d`, whichever points towards +z (then +y, then +x on ties).
#[inline]
pub fn canonical(d: Vec3) -> Vec3 {
    let flip = d.z < 0.0 || (d.z == 0.0 && (d.y < 0.0 || (d.y == 0.0 && d.x < 0.0)));
    if flip {
        -d
    } else {
        d
    }
}

/// t_i of the 32 equal intervals of the chord `start → end`: each interval
/// marched with ⌈length/step⌉ equal sub-steps sharing one jitter.
pub fn interval_transmittances<V: VolumeAccess>(
    v: &V,
    cube: &UnitCube,
    start: Vec3,
    end: Vec3,
    step: f32,
    rng: &mut Pcg32,
) -> [f64; INTERVALS] {
    let delta = (end - start) / INTERVALS as f32;
    let local_len = delta.length();
    let world_len = (cube.to_world * delta).length() as f64;
    let n = ((local_len / step.max(1e-6)).ceil() as u32).clamp(1, 1 << 16);
    let mut lookups = 0;
    std::array::from_fn(|i| {
        let u = rng.next_f32();
        let mut sum = 0.0f64;
        for j in 0..n {
            let s = (i as f32 + (j as f32 + u) / n as f32) / INTERVALS as f32;
            let p = (start + (end - start) * s) * cube.dims;
            sum += sigma_t_at(v, p, rng, &mut lookups) as f64;
        }
        (-(sum / n as f64) * world_len).exp()
    })
}

//! Queries along a ray (Hansen 2025 §3.4.2–§3.5, §3.9; the thesis's Figs. 8.2
//! and 8.3): a pin's bits are read along the *query ray's own chord*
//! through the unit cube, one bit per 1/32 of it, starting at the bit that
//! holds the query's start (that interval counts whole), reversed when the
//! query runs against the pins' +z orientation. Distances come back in the
//! query ray's parameter (world units when the unit-cube ray carries the
//! world parameter).

use super::mask::sample_mask;
use super::pin::{canonical, Pin};
use fogbank_math::{Aabb, Pcg32, Ray, Vec3};

/// Where a query segment starts among the 32 bits of its chord.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chord {
    /// The chord's length in the ray parameter (L; one bit is L/32).
    pub length: f32,
    /// The relative position of the query's start on the chord, clamped
    /// to [0, 0.9999] as in the thesis.
    pub rel: f32,
    /// The start's bit, counted from the chord's start: ⌊32·rel⌋ ∈ [0, 31].
    pub offset: u32,
    /// Bits are reversed (the query runs towards −z).
    pub reversed: bool,
}

impl Chord {
    /// The chord of the unit-cube `ray` and the bit of `t_start` on it
    /// (`None` when the line misses the cube).
    pub fn new(ray: &Ray, t_start: f32) -> Option<Chord> {
        let (a, b) =
            Aabb::new(Vec3::ZERO, Vec3::ONE).intersect(ray, f32::NEG_INFINITY, f32::INFINITY)?;
        let length = b - a;
        if length.is_nan() || length <= 0.0 {
            return None;
        }
        let rel = ((t_start - a) / length).clamp(0.0, 0.9999);
        Some(Chord {
            length,
            rel,
            offset: (rel * 32.0) as u32,
            reversed: canonical(ray.d) != ray.d,
        })
    }

    /// `mask` with its first bit at the chord's start, then shifted so the
    /// start's bit is the most significant.
    #[inline]
    fn aligned(&self, mask: u32) -> u32 {
        let m = if self.reversed {
            mask.reverse_bits()
        } else {
            mask
        };
        m << self.offset
    }

    /// MSB distance sampling (Fig. 8.2) with a collision mask M̃ = Ĩ ∧ H:
    /// the first set bit at or after the start's, the distance from the
    /// start uniform inside it (`u` ∈ [0, 1)); `None` for an empty mask,
    /// no bit ahead, or a distance beyond `max_len`.
    pub fn sample_distance(&self, collision_mask: u32, max_len: f32, u: f32) -> Option<f32> {
        if collision_mask == 0 {
            return None;
        }
        let m = self.aligned(collision_mask);
        if m == 0 {
            return None;
        }
        let d = (m.leading_zeros() as f32 + u) * self.length / 32.0;
        (d <= max_len).then_some(d)
    }

    /// The set bits of Ĩ from the start's bit to the bit holding the end
    /// (`max_len` ahead; included; past the exit, the last bit) — Eq. 3.7's
    /// exponent, Fig. 8.3.
    pub fn count(&self, mask: u32, max_len: f32) -> u32 {
        if mask == 0 {
            return 0;
        }
        let rel_end = self.rel + max_len / self.length;
        let keep_from = ((1.0 - rel_end).clamp(0.0, 0.9999) * 32.0) as u32;
        let m = if self.reversed {
            mask.reverse_bits()
        } else {
            mask
        };
        ((m & (u32::MAX << keep_from)) << self.offset).count_ones()
    }

    /// A distance sampled with `pin` (§3.4.3): Ĩ AND a fresh majorant mask
    /// of density 1 − t_min from `iterations` bisection steps.
    pub fn distance(
        &self,
        pin: &Pin,
        max_len: f32,
        iterations: u32,
        rng: &mut Pcg32,
    ) -> Option<f32> {
        if pin.mask == 0 {
            return None;
        }
        let (h, _) = sample_mask(1.0 - pin.t_min, iterations, rng);
        self.sample_distance(pin.mask & h, max_len, rng.next_f32())
    }

    /// Eq. 3.7: T̃ = t_min^popcount over `[start, start + max_len]`.
    pub fn transmittance(&self, pin: &Pin, max_len: f32) -> f32 {
        pin.t_min.powi(self.count(pin.mask, max_len) as i32)
    }
}

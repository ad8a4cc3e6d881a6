//! The exact discrete reference and the row samplers of Hansen 2025 §3.4.1–
//! §3.4.3 (Fig. 3.4): the free-flight distribution over 32 intervals of
//! transmittances t_i, sampled exactly (Eq. 3.1), from n stored rows of the
//! collision matrix M (undecomposed, P(M_ji = 1) = 1 − t_i) and from n rows
//! of the ratio matrix I with a fresh majorant row H per sample (Eq. 3.4–
//! 3.6). Index 32 stands for "no collision".

use super::mask::bernoulli_mask;
use super::pin::{Pin, INTERVALS};
use fogbank_math::Pcg32;

/// Hansen 2025 Eq. 3.3 (factors in the right order): P(first collision in
/// interval i) = (1 − t_i) Π_{k<i} t_k; entry 32 is P(no collision) = Π t_k.
pub fn collision_probabilities(t: &[f64; INTERVALS]) -> [f64; INTERVALS + 1] {
    let mut out = [0.0; INTERVALS + 1];
    let mut through = 1.0;
    for (i, &ti) in t.iter().enumerate() {
        out[i] = (1.0 - ti) * through;
        through *= ti;
    }
    out[INTERVALS] = through;
    out
}

/// Eq. 3.1 (discrete CDF sampling): the first interval whose cumulative
/// collision probability reaches ξ, or 32.
pub fn sample_exact(t: &[f64; INTERVALS], rng: &mut Pcg32) -> usize {
    let xi = rng.next_f64();
    let mut cdf = 0.0;
    for (i, c) in collision_probabilities(t)
        .iter()
        .take(INTERVALS)
        .enumerate()
    {
        cdf += c;
        if xi < cdf {
            return i;
        }
    }
    INTERVALS
}

/// The first set bit from the most significant (interval 0), or 32.
#[inline]
pub fn first_interval(mask: u32) -> usize {
    mask.leading_zeros() as usize
}

/// `rows` rows of the collision matrix M (§3.4.2), interval i at bit 31 − i.
pub fn collision_rows(t: &[f64; INTERVALS], rows: usize, rng: &mut Pcg32) -> Vec<u32> {
    (0..rows)
        .map(|_| {
            (0..INTERVALS).fold(0u32, |m, i| {
                m | (((rng.next_f64() < 1.0 - t[i]) as u32) << (31 - i))
            })
        })
        .collect()
}

/// `rows` rows of the ratio matrix I (Eq. 3.5), as pins sharing t_min.
pub fn ratio_rows(t: &[f64; INTERVALS], rows: usize, rng: &mut Pcg32) -> Vec<Pin> {
    (0..rows)
        .map(|_| Pin::from_transmittances(t, rng))
        .collect()
}

/// One decomposed sample from a stored ratio row (Eq. 3.4): M = Ĩ ∧ H with
/// an exact Bernoulli(1 − t_min) majorant row H.
pub fn sample_decomposed(pin: &Pin, rng: &mut Pcg32) -> usize {
    first_interval(pin.mask & bernoulli_mask(1.0 - pin.t_min as f64, rng))
}

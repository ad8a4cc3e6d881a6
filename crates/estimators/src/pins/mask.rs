//! Majorant masks H (Hansen 2025 §3.8, Eq. 3.11): a random 32-bit mask whose
//! bits are 1 with probability ≈ 1 − t_min, made by bisection between an
//! all-ones and an all-zeros mask: (A ∧ U) ∨ (B ∧ ¬U) with a uniform random
//! word U has the mean of A's and B's densities, so k steps reach an odd
//! multiple of 2^−k within 2^−k of the target, one random word per step.

use fogbank_math::Pcg32;

/// The thesis's iteration count (Fig. 4.2: little changes beyond 3).
pub const DEFAULT_ITERATIONS: u32 = 5;

/// A mask of bit density `p` to within 2^−`iterations` (Eq. 3.11; the
/// thesis's `gen_sample_mask`): the last midpoint of the bisection and its
/// exact density. With `iterations` = 0 the mask is all zeros.
pub fn sample_mask(p: f32, iterations: u32, rng: &mut Pcg32) -> (u32, f32) {
    let (mut upper, mut lower) = (u32::MAX, 0u32);
    let (mut p_upper, mut p_lower) = (1.0f32, 0.0f32);
    let (mut middle, mut p_middle) = (0u32, 0.0f32);
    for _ in 0..iterations {
        let u = rng.next_u32();
        middle = (u & lower) | (!u & upper);
        p_middle = 0.5 * (p_lower + p_upper);
        if p_middle > p {
            upper = middle;
            p_upper = p_middle;
        } else {
            lower = middle;
            p_lower = p_middle;
        }
    }
    (middle, p_middle)
}

/// A mask whose bits are independent Bernoulli(`p`) draws, exactly (for
/// tests and the exact reference: one uniform number per bit).
pub fn bernoulli_mask(p: f64, rng: &mut Pcg32) -> u32 {
    (0..32).fold(0u32, |m, i| m | (((rng.next_f64() < p) as u32) << i))
}

#[cfg(test)]
mod mask_test {
    use super::*;

    /// The density is the last midpoint, an odd multiple of 2^−k within
    /// 2^−k of the target (both ends included), and the measured bit
    /// frequency matches it, bit by bit and without pairwise correlation.
    #[test]
    fn density_is_the_last_midpoint_within_two_to_minus_k() {
        let mut rng = Pcg32::new(4, 2);
        for k in [1u32, 3, 5, 8] {
            for target in [0.0f32, 1e-3, 0.03, 0.2, 0.5, 0.77, 0.97, 0.999, 1.0] {
                let step = 0.5f32.powi(k as i32);
                let (_, d) = sample_mask(target, k, &mut rng);
                assert!((d - target).abs() <= step, "k {k}, target {target}: {d}");
                let odd = (d / step).round() as u32;
                assert!(
                    odd % 2 == 1 && (odd as f32 * step - d).abs() < 1e-6,
                    "k {k}: {d}"
                );
                // Bit frequencies and pairwise independence over many masks.
                let n = 20_000;
                let mut ones = [0u32; 32];
                let mut both = 0u32;
                for _ in 0..n {
                    let (m, dm) = sample_mask(target, k, &mut rng);
                    assert_eq!(dm, d);
                    for (b, o) in ones.iter_mut().enumerate() {
                        *o += (m >> b) & 1;
                    }
                    both += (m & 1) & ((m >> 7) & 1);
                }
                let sd = (d * (1.0 - d) / n as f32).sqrt();
                for (b, &o) in ones.iter().enumerate() {
                    let f = o as f32 / n as f32;
                    assert!(
                        (f - d).abs() <= 5.0 * sd + 1e-6,
                        "k {k} bit {b}: {f} vs {d}"
                    );
                }
                let pair = both as f32 / n as f32;
                let sd2 = (d * d * (1.0 - d * d) / n as f32).sqrt();
                assert!(
                    (pair - d * d).abs() <= 5.0 * sd2 + 1e-6,
                    "k {k}: pair {pair} vs {}",
                    d * d
                );
            }
        }
        assert_eq!(sample_mask(0.3, 0, &mut rng), (0, 0.0));
    }
}

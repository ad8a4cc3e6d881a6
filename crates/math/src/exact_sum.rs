//! Order-independent sums of samples: a 256-bit two's-complement fixed-point
//! number with 128 fraction bits. Integer addition is associative, so a
//! pixel's sum is the same bit for bit however its samples are split into
//! shards, threads or passes and whatever order the parts are added in —
//! which f64 accumulation cannot promise. This is what makes `fogbank merge`
//! equal a single-process render exactly.
//!
//! Range: a term must be smaller in magnitude than [`TERM_LIMIT`] (2¹⁰⁰),
//! so 2³¹ of them leave headroom; bits below 2⁻¹²⁸ are dropped (truncation
//! toward zero, the same for every term wherever it is added). A sample
//! `x` contributes `x` to one sum and `x²` (exact in f64) to another, so
//! radiance samples are limited to |x| < 2⁵⁰ ([`SAMPLE_LIMIT`]); callers
//! count larger ones as non-finite.

/// Magnitude below which a term is representable with headroom for 2³¹ terms.
pub const TERM_LIMIT: f64 = 1.2676506002282294e30; // 2^100
/// Largest sample magnitude (exclusive) whose square is a valid term.
pub const SAMPLE_LIMIT: f32 = 1.1258999e15; // 2^50
const FRACTION_BITS: i32 = 128;

/// Σ of f64 terms, exactly as a multiple of 2⁻¹²⁸: a 256-bit two's-complement
/// integer in two halves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ExactSum {
    lo: u128,
    hi: u128,
}

impl ExactSum {
    pub const ZERO: ExactSum = ExactSum { lo: 0, hi: 0 };

    /// The term `v` truncated toward zero to a multiple of 2⁻¹²⁸.
    pub fn from_f64(v: f64) -> ExactSum {
        let mut s = ExactSum::ZERO;
        s.add_f64(v);
        s
    }

    /// Adds the term `v` (|v| < [`TERM_LIMIT`]; a larger or non-finite one
    /// is a caller's bug and is skipped), truncated toward zero to a
    /// multiple of 2⁻¹²⁸. Adds the shifted mantissa in place: the hot path
    /// of every film.
    #[inline]
    pub fn add_f64(&mut self, v: f64) {
        let bits = v.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i32;
        // Zero and subnormals (below 2⁻¹⁰²², far under the resolution).
        if biased == 0 {
            return;
        }
        if biased >= 1023 + 100 {
            debug_assert!(false, "term {v} out of range");
            return;
        }
        let mantissa = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
        // v = mantissa · 2^(biased − 1075); the raw integer is v · 2¹²⁸.
        let shift = biased - 1075 + FRACTION_BITS;
        // The raw term as (low half, high half) of 256 bits; below 2¹⁰⁰ it
        // ends under bit 228, so the high half never overflows.
        let (lo, hi) = if shift < 0 {
            if shift <= -64 {
                return;
            }
            ((mantissa >> -shift) as u128, 0)
        } else if shift < 128 {
            let wide = (mantissa as u128) << (shift % 64);
            if shift < 64 {
                (wide, 0)
            } else {
                // Spans bits 64..181: the low half's top limb and beyond.
                (wide << 64, wide >> 64)
            }
        } else {
            (0, (mantissa as u128) << (shift - 128))
        };
        let term = ExactSum { lo, hi };
        if bits >> 63 == 0 {
            self.add(&term);
        } else {
            self.sub(&term);
        }
    }

    /// Adds `other` (wrapping; the range above keeps it from wrapping).
    #[inline]
    pub fn add(&mut self, other: &ExactSum) {
        let (lo, carry) = self.lo.overflowing_add(other.lo);
        self.lo = lo;
        self.hi = self.hi.wrapping_add(other.hi).wrapping_add(carry as u128);
    }

    #[inline]
    fn sub(&mut self, other: &ExactSum) {
        let (lo, borrow) = self.lo.overflowing_sub(other.lo);
        self.lo = lo;
        self.hi = self.hi.wrapping_sub(other.hi).wrapping_sub(borrow as u128);
    }

    pub fn is_negative(&self) -> bool {
        self.hi >> 127 == 1
    }

    pub fn negated(&self) -> ExactSum {
        let mut r = ExactSum::ZERO;
        r.sub(self);
        r
    }

    fn limbs(&self) -> [u64; 4] {
        [
            self.lo as u64,
            (self.lo >> 64) as u64,
            self.hi as u64,
            (self.hi >> 64) as u64,
        ]
    }

    /// The magnitude as an unsigned 256-bit integer (raw units).
    fn magnitude(&self) -> [u64; 4] {
        if self.is_negative() {
            self.negated().limbs()
        } else {
            self.limbs()
        }
    }

    /// The nearest f64 (within one ulp; deterministic).
    pub fn to_f64(&self) -> f64 {
        let m = limbs_to_f64(&self.magnitude()) * (-(FRACTION_BITS as f64)).exp2();
        if self.is_negative() {
            -m
        } else {
            m
        }
    }

    pub fn to_le_bytes(&self) -> [u8; 32] {
        let mut b = [0u8; 32];
        b[..16].copy_from_slice(&self.lo.to_le_bytes());
        b[16..].copy_from_slice(&self.hi.to_le_bytes());
        b
    }

    pub fn from_le_bytes(b: &[u8; 32]) -> ExactSum {
        ExactSum {
            lo: u128::from_le_bytes(b[..16].try_into().unwrap()),
            hi: u128::from_le_bytes(b[16..].try_into().unwrap()),
        }
    }
}

/// An unsigned little-endian multi-limb integer as the nearest f64 (the top
/// two nonzero limbs decide it, within one ulp).
fn limbs_to_f64(l: &[u64]) -> f64 {
    let Some(top) = l.iter().rposition(|&x| x != 0) else {
        return 0.0;
    };
    let hi = l[top] as f64 * (64.0 * top as f64).exp2();
    let lo = if top > 0 {
        l[top - 1] as f64 * (64.0 * (top - 1) as f64).exp2()
    } else {
        0.0
    };
    hi + lo
}

/// Unsigned 256 × 256 → 512-bit product.
fn mul_wide(a: &[u64; 4], b: &[u64; 4]) -> [u64; 8] {
    let mut r = [0u64; 8];
    for i in 0..4 {
        let mut carry = 0u128;
        for j in 0..4 {
            let t = a[i] as u128 * b[j] as u128 + r[i + j] as u128 + carry;
            r[i + j] = t as u64;
            carry = t >> 64;
        }
        r[i + 4] = carry as u64;
    }
    r
}

/// The unbiased sample variance of `n` samples from their exact sums,
/// s² = (n·Σx² − (Σx)²) / (n (n − 1)), with the numerator computed exactly
/// in 512-bit integers: a constant pixel gets exactly 0 (when its squares
/// are representable), and the result does not depend on how the samples
/// were split. 0 for n < 2.
pub fn sample_variance(n: u32, sum: &ExactSum, sum_sq: &ExactSum) -> f64 {
    if n < 2 {
        return 0.0;
    }
    // Both terms in units of 2⁻²⁵⁶: n·Σx²·2¹²⁸ and (Σx)².
    let s = sum.magnitude();
    let square = mul_wide(&s, &s);
    let q = sum_sq.magnitude();
    let scaled = mul_wide(&q, &[n as u64, 0, 0, 0]);
    let mut lhs = [0u64; 8];
    lhs[2..8].copy_from_slice(&scaled[0..6]);
    // lhs − square, clamped at 0 (truncated squares can undershoot by ulps).
    let mut d = [0u64; 8];
    let mut borrow = false;
    for i in 0..8 {
        let (a, b1) = lhs[i].overflowing_sub(square[i]);
        let (b, b2) = a.overflowing_sub(borrow as u64);
        d[i] = b;
        borrow = b1 || b2;
    }
    if borrow || sum_sq.is_negative() {
        return 0.0;
    }
    let n = n as f64;
    limbs_to_f64(&d) * (-256.0f64).exp2() / (n * (n - 1.0))
}

#[cfg(test)]
mod exact_sum_test {
    use super::*;
    use crate::Pcg32;

    #[test]
    fn round_trips_representable_values() {
        for v in [
            0.0,
            1.0,
            -1.0,
            0.3f32 as f64,
            -1e-20,
            7.5e12,
            2.0f64.powi(-128),
            -3.0e29,
        ] {
            assert_eq!(ExactSum::from_f64(v).to_f64(), v, "{v}");
        }
        // Below the resolution: truncated toward zero.
        assert_eq!(ExactSum::from_f64(2.0f64.powi(-130)).to_f64(), 0.0);
        assert_eq!(ExactSum::from_f64(-1e-300).to_f64(), 0.0);
        // Truncation is toward zero on both sides, so −v is the negation of v.
        for v in [1.0 + 2f64.powi(-52), 3.3e-38, 1e-39, 6.1e29, 0.1] {
            assert_eq!(
                ExactSum::from_f64(-v),
                ExactSum::from_f64(v).negated(),
                "{v}"
            );
        }
    }

    /// The point of the type: any split and order of the same terms gives
    /// the same bits, where f64 summation does not.
    #[test]
    fn sums_do_not_depend_on_order_or_grouping() {
        let mut rng = Pcg32::new(3, 1);
        let terms: Vec<f64> = (0..4000)
            .map(|i| {
                let x = rng.next_f32() as f64 - 0.3;
                x * 10f64.powi((i % 23) - 11)
            })
            .collect();
        let forward = terms.iter().fold(ExactSum::ZERO, |mut s, &t| {
            s.add_f64(t);
            s
        });
        let mut parts = [ExactSum::ZERO; 7];
        for (i, &t) in terms.iter().enumerate().rev() {
            parts[i * 7 / terms.len()].add_f64(t);
        }
        let mut grouped = ExactSum::ZERO;
        for p in parts.iter().rev() {
            grouped.add(p);
        }
        assert_eq!(forward, grouped);
        let f64_forward: f64 = terms.iter().sum();
        let f64_backward: f64 = terms.iter().rev().sum();
        assert_ne!(f64_forward, f64_backward, "the terms must be able to tell");
        assert!((forward.to_f64() - f64_forward).abs() <= 1e-12 * f64_forward.abs().max(1.0));
    }

    #[test]
    fn negative_sums_and_bytes_round_trip() {
        let mut s = ExactSum::from_f64(2.5);
        s.add_f64(-4.0);
        assert_eq!(ExactSum::from_f64(-1.5), s);
        assert!(s.is_negative());
        assert_eq!(s.to_f64(), -1.5);
        assert_eq!(ExactSum::from_le_bytes(&s.to_le_bytes()), s);
    }

    #[test]
    fn sample_variance_is_exact_for_constants_and_matches_two_pass() {
        let (mut s, mut q) = (ExactSum::ZERO, ExactSum::ZERO);
        for _ in 0..1000 {
            s.add_f64(0.3f32 as f64);
            q.add_f64((0.3f32 as f64).powi(2));
        }
        assert_eq!(sample_variance(1000, &s, &q), 0.0);
        let xs = [1.5f64, -2.25, 0.125, 7.0, 3.0e-3];
        let (mut s, mut q) = (ExactSum::ZERO, ExactSum::ZERO);
        for &x in &xs {
            s.add_f64(x);
            q.add_f64(x * x);
        }
        let m = xs.iter().sum::<f64>() / 5.0;
        let two_pass = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / 4.0;
        let v = sample_variance(5, &s, &q);
        assert!(
            (v - two_pass).abs() <= 1e-14 * two_pass,
            "{v} vs {two_pass}"
        );
        assert_eq!(sample_variance(1, &s, &q), 0.0);
    }
}

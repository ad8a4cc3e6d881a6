//! Random numbers: PCG32 streams keyed by (pixel, sample index, dimension)
//! and the PCG3D hash. A render is a function of scene, seed and sample index
//! only, because every stream is derived from that key and never from thread
//! or tile order.

/// PCG32 (O'Neill 2014, XSH-RR output, 64-bit LCG state).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

const PCG_MULT: u64 = 6364136223846793005;

impl Pcg32 {
    /// Seeds like the reference `pcg32_srandom_r(initstate, initseq)`.
    pub fn new(init_state: u64, init_seq: u64) -> Self {
        let mut rng = Pcg32 {
            state: 0,
            inc: (init_seq << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(init_state);
        rng.next_u32();
        rng
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1) with 24 bits, so that `1 - u` is never 0 and the
    /// value is exactly representable (the GPU uses the same mapping).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in [0, 1) with 53 bits, for the analysis tools.
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        let hi = (self.next_u32() >> 5) as u64;
        let lo = (self.next_u32() >> 6) as u64;
        ((hi << 26) | lo) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }
}

/// The key of one random stream: scene seed, pixel, sample index and a
/// dimension (the purpose: camera jitter, estimator, light sampling, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleKey {
    pub seed: u32,
    pub pixel: u32,
    pub sample: u32,
    pub dimension: u32,
}

impl SampleKey {
    pub fn rng(&self) -> Pcg32 {
        let h = pcg3d([self.pixel, self.sample, self.seed]);
        let state = ((h[0] as u64) << 32) | h[1] as u64;
        let seq = ((h[2] as u64) << 32) | self.dimension as u64;
        Pcg32::new(state, seq)
    }
}

/// PCG3D hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering").
/// Used for stochastic trilinear filtering: three independent jitters from
/// one 32-bit draw.
#[inline]
pub fn pcg3d(v: [u32; 3]) -> [u32; 3] {
    let mut x = v[0].wrapping_mul(1664525).wrapping_add(1013904223);
    let mut y = v[1].wrapping_mul(1664525).wrapping_add(1013904223);
    let mut z = v[2].wrapping_mul(1664525).wrapping_add(1013904223);
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    x ^= x >> 16;
    y ^= y >> 16;
    z ^= z >> 16;
    x = x.wrapping_add(y.wrapping_mul(z));
    y = y.wrapping_add(z.wrapping_mul(x));
    z = z.wrapping_add(x.wrapping_mul(y));
    [x, y, z]
}

/// Maps a 32-bit hash to [0, 1) exactly as [`Pcg32::next_f32`] does.
#[inline]
pub fn unit_f32(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod rng_test {
    use super::*;

    #[test]
    fn pcg32_matches_reference_sequence() {
        // First outputs of the PCG reference demo `pcg32-demo` with
        // initstate 42, initseq 54.
        let mut r = Pcg32::new(42, 54);
        let expected = [
            0xa15c02b7u32,
            0x7b47f409,
            0xba1d3330,
            0x83d2f293,
            0xbfa4784b,
            0xcbed606e,
        ];
        for e in expected {
            assert_eq!(r.next_u32(), e);
        }
    }

    #[test]
    fn unit_floats_are_in_range_and_uniform() {
        let mut r = SampleKey {
            seed: 1,
            pixel: 2,
            sample: 3,
            dimension: 4,
        }
        .rng();
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let u = r.next_f32();
            assert!((0.0..1.0).contains(&u));
            sum += u as f64;
        }
        let mean = sum / n as f64;
        // SE of the mean of U(0,1) is sqrt(1/12/n) ≈ 9.1e-4.
        assert!((mean - 0.5).abs() < 4.0 * (1.0f64 / 12.0 / n as f64).sqrt());
    }

    #[test]
    fn keys_give_distinct_streams() {
        let a = SampleKey {
            seed: 0,
            pixel: 0,
            sample: 0,
            dimension: 0,
        }
        .rng()
        .next_u32();
        let b = SampleKey {
            seed: 0,
            pixel: 0,
            sample: 1,
            dimension: 0,
        }
        .rng()
        .next_u32();
        let c = SampleKey {
            seed: 0,
            pixel: 0,
            sample: 0,
            dimension: 1,
        }
        .rng()
        .next_u32();
        assert!(a != b && a != c && b != c);
    }
}

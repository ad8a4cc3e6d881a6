//! Fixed-width quantised leaves (NanoVDB's `Fp8`, `Fp16`): per leaf, the
//! minimum and maximum of all 512 values give a minimum and a quantum
//! `(max − min) / (2^bits − 1)`; each value is stored as the code
//! `⌊(v − min) · (2^bits − 1) / (max − min) + ½⌋` and read back as
//! `code · quantum + min` in `f32`, as NanoVDB's converter encodes it
//! without dithering and its accessors decode it.

use super::nanovdb_stats::Stats;

pub(crate) struct Quantised {
    pub(crate) minimum: f32,
    pub(crate) quantum: f32,
    /// One code per voxel, in the leaf's voxel order.
    pub(crate) codes: Vec<u16>,
}

impl Quantised {
    pub(crate) fn new(values: &[f32; 512], bits: u32) -> Quantised {
        let min = values.iter().copied().fold(f32::MAX, f32::min);
        let max = values.iter().copied().fold(f32::MIN, f32::max);
        let levels = ((1u32 << bits) - 1) as f32;
        // The range and each offset from the minimum in f32, the scale,
        // product and rounding in f64: what reproduces NanoVDB's codes bit
        // for bit (other mixes round some values within an ulp of a half
        // the other way).
        let levels64 = levels as f64;
        let encode = if max > min {
            levels64 / (max - min) as f64
        } else {
            0.0
        };
        let codes = values
            .iter()
            .map(|&v| (encode * (v - min) as f64 + 0.5).clamp(0.0, levels64) as u16)
            .collect();
        Quantised {
            minimum: min,
            quantum: (max - min) / levels,
            codes,
        }
    }

    /// The values as readers decode them.
    pub(crate) fn decoded(&self) -> Vec<f32> {
        self.codes
            .iter()
            .map(|&c| c as f32 * self.quantum + self.minimum)
            .collect()
    }

    /// The leaf's minimum, maximum and average in quanta above the
    /// minimum, and its standard deviation in quanta, rounded (NanoVDB's
    /// `u16` statistics of quantised leaves).
    pub(crate) fn stats_codes(&self, s: &Stats) -> [u16; 4] {
        let [min, max, avg, std] = s.stored();
        let q = |v: f32| (v / self.quantum + 0.5) as u16;
        [
            q(min - self.minimum),
            q(max - self.minimum),
            q(avg - self.minimum),
            q(std),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_to_nearest_and_decode_within_half_a_quantum() {
        let values: [f32; 512] = std::array::from_fn(|i| (i as f32 * 0.37).sin());
        for bits in [8, 16] {
            let q = Quantised::new(&values, bits);
            for (d, v) in q.decoded().iter().zip(values) {
                assert!((d - v).abs() <= 0.5 * q.quantum + 1e-6);
            }
        }
        let flat = Quantised::new(&[2.5; 512], 8);
        assert_eq!(flat.decoded(), vec![2.5; 512]);
    }
}

//! Per-pixel accumulation: exact sums and squared sums ([`ExactSum`], so the
//! image does not depend on how samples are split across threads, passes or
//! shards — `fogbank merge` relies on it), a per-pixel sample count (a
//! render interrupted mid-pass stays unbiased per pixel), and the counts of
//! dropped non-finite samples.

use fogbank_image::image_io::Image;
use fogbank_math::exact_sum::{sample_variance, SAMPLE_LIMIT};
use fogbank_math::{ExactSum, Vec3};

/// One pixel's Σx and Σx² per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelSums {
    pub sum: [ExactSum; 3],
    pub sum_sq: [ExactSum; 3],
}

/// What happened to a sample offered to a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accumulated {
    Added,
    /// A NaN channel: dropped and counted.
    Nan,
    /// An infinite channel, or one at least [`SAMPLE_LIMIT`] (2⁵⁰) in
    /// magnitude, whose square the exact sums cannot hold: dropped and
    /// counted with the infinite ones.
    Inf,
}

impl PixelSums {
    /// Adds one sample to the sums and `count`, unless it is non-finite.
    #[inline]
    pub fn add(&mut self, count: &mut u32, l: Vec3) -> Accumulated {
        let v = l.to_array();
        if v.iter().any(|c| c.is_nan()) {
            return Accumulated::Nan;
        }
        // NaN is handled above, so `>=` catches the infinities too.
        if v.iter().any(|c| c.abs() >= SAMPLE_LIMIT) {
            return Accumulated::Inf;
        }
        for (c, &x) in v.iter().enumerate() {
            let x = x as f64;
            self.sum[c].add_f64(x);
            self.sum_sq[c].add_f64(x * x);
        }
        *count += 1;
        Accumulated::Added
    }

    /// Adds another pixel's sums (exact, so in any order).
    pub fn merge(&mut self, o: &PixelSums) {
        for c in 0..3 {
            self.sum[c].add(&o.sum[c]);
            self.sum_sq[c].add(&o.sum_sq[c]);
        }
    }
}

#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub sums: Vec<PixelSums>,
    pub count: Vec<u32>,
    pub lookups: u64,
    pub nan_samples: u64,
    pub inf_samples: u64,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Film {
            width,
            height,
            sums: vec![PixelSums::default(); n],
            count: vec![0; n],
            lookups: 0,
            nan_samples: 0,
            inf_samples: 0,
        }
    }

    /// Adds one sample to pixel `i`, counting a dropped one.
    pub fn add_sample(&mut self, i: usize, l: Vec3) -> Accumulated {
        let r = self.sums[i].add(&mut self.count[i], l);
        match r {
            Accumulated::Added => {}
            Accumulated::Nan => self.nan_samples += 1,
            Accumulated::Inf => self.inf_samples += 1,
        }
        r
    }

    /// Sets pixel `i` from moments kept elsewhere (the GPU's running means),
    /// each truncated to the sums' resolution.
    pub fn set_moments(&mut self, i: usize, sum: [f64; 3], sum_sq: [f64; 3], count: u32) {
        self.sums[i] = PixelSums {
            sum: sum.map(ExactSum::from_f64),
            sum_sq: sum_sq.map(ExactSum::from_f64),
        };
        self.count[i] = count;
    }

    /// Adds another film of the same size: sums, counts and totals (exact,
    /// so merging parts in any grouping gives the same film).
    pub fn merge(&mut self, o: &Film) {
        assert_eq!((self.width, self.height), (o.width, o.height));
        for (a, b) in self.sums.iter_mut().zip(&o.sums) {
            a.merge(b);
        }
        for (a, b) in self.count.iter_mut().zip(&o.count) {
            *a += b;
        }
        self.lookups += o.lookups;
        self.nan_samples += o.nan_samples;
        self.inf_samples += o.inf_samples;
    }

    /// Pixel `i`'s Σx per channel.
    pub fn sum(&self, i: usize) -> [f64; 3] {
        self.sums[i].sum.map(|s| s.to_f64())
    }

    /// Pixel `i`'s Σx² per channel.
    pub fn sum_sq(&self, i: usize) -> [f64; 3] {
        self.sums[i].sum_sq.map(|s| s.to_f64())
    }

    /// Pixel `i`'s unbiased sample variance (of one sample) per channel; 0
    /// below two samples.
    pub fn sample_variance(&self, i: usize) -> [f64; 3] {
        let s = &self.sums[i];
        std::array::from_fn(|c| sample_variance(self.count[i], &s.sum[c], &s.sum_sq[c]))
    }

    /// Per-pixel mean; pixels without samples are 0.
    pub fn mean(&self) -> Vec<[f32; 3]> {
        (0..self.sums.len())
            .map(|i| {
                let n = self.count[i];
                if n == 0 {
                    [0.0; 3]
                } else {
                    self.sum(i).map(|v| (v / n as f64) as f32)
                }
            })
            .collect()
    }

    /// Per-pixel variance of the mean: s² / n with the unbiased sample
    /// variance s²; 0 where fewer than two samples exist.
    pub fn variance_of_mean(&self) -> Vec<[f32; 3]> {
        (0..self.sums.len())
            .map(|i| {
                let n = self.count[i] as f64;
                self.sample_variance(i).map(|s2| (s2 / n) as f32)
            })
            .collect()
    }

    /// The per-pixel means with the variance of each mean: the image that
    /// [`fogbank_image::metrics::ztest`] compares with another.
    pub fn mean_image(&self) -> Image {
        Image {
            width: self.width as usize,
            height: self.height as usize,
            rgb: self.mean(),
            variance: Some(self.variance_of_mean()),
            is_srgb8: false,
        }
    }

    /// Per pixel, channel `c`: the difference of this film's mean and
    /// `other`'s, with the variance of that difference (the films
    /// independent) — what a per-pixel z-test divides.
    pub fn mean_difference(&self, other: &Film, c: usize) -> Vec<(f64, f64)> {
        let (ma, va) = (self.mean(), self.variance_of_mean());
        let (mb, vb) = (other.mean(), other.variance_of_mean());
        (0..ma.len())
            .map(|k| ((ma[k][c] - mb[k][c]) as f64, (va[k][c] + vb[k][c]) as f64))
            .collect()
    }

    pub fn total_samples(&self) -> u64 {
        self.count.iter().map(|&c| c as u64).sum()
    }

    pub fn min_spp(&self) -> u32 {
        self.count.iter().copied().min().unwrap_or(0)
    }

    /// Per-channel mean of the image.
    pub fn image_mean(&self) -> [f64; 3] {
        let m = self.mean();
        let n = m.len().max(1) as f64;
        std::array::from_fn(|c| m.iter().map(|p| p[c] as f64).sum::<f64>() / n)
    }
}

#[cfg(test)]
mod film_test {
    use super::*;

    #[test]
    fn merging_split_samples_equals_adding_them_in_one_film() {
        let samples: Vec<Vec3> = (0..50)
            .map(|k| Vec3::new(0.1 * k as f32, 1.0 / (k + 1) as f32, -0.37 * (k % 7) as f32))
            .collect();
        let mut whole = Film::new(2, 1);
        let (mut a, mut b) = (Film::new(2, 1), Film::new(2, 1));
        for (k, &s) in samples.iter().enumerate() {
            whole.add_sample(k % 2, s);
            if k < 17 { &mut a } else { &mut b }.add_sample(k % 2, s);
        }
        b.merge(&a);
        assert_eq!(b.sums, whole.sums);
        assert_eq!(b.count, whole.count);
        assert_eq!(b.variance_of_mean(), whole.variance_of_mean());
    }

    #[test]
    fn non_finite_and_huge_samples_are_dropped_and_counted() {
        let mut f = Film::new(1, 1);
        assert_eq!(
            f.add_sample(0, Vec3::new(f32::NAN, 0.0, 0.0)),
            Accumulated::Nan
        );
        assert_eq!(
            f.add_sample(0, Vec3::new(0.0, f32::INFINITY, 0.0)),
            Accumulated::Inf
        );
        assert_eq!(
            f.add_sample(0, Vec3::new(0.0, 0.0, -2e15)),
            Accumulated::Inf
        );
        assert_eq!(f.add_sample(0, Vec3::splat(1e15)), Accumulated::Added);
        assert_eq!((f.count[0], f.nan_samples, f.inf_samples), (1, 1, 2));
        assert_eq!(f.mean()[0], [1e15; 3]);
    }
}

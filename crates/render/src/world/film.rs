//! Per-pixel accumulation: sums and squared sums in f64, a per-pixel sample
//! count (a render interrupted mid-pass stays unbiased per pixel), and the
//! counts of dropped non-finite samples.

#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub sum: Vec<[f64; 3]>,
    pub sum_sq: Vec<[f64; 3]>,
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
            sum: vec![[0.0; 3]; n],
            sum_sq: vec![[0.0; 3]; n],
            count: vec![0; n],
            lookups: 0,
            nan_samples: 0,
            inf_samples: 0,
        }
    }

    /// Per-pixel mean; pixels without samples are 0.
    pub fn mean(&self) -> Vec<[f32; 3]> {
        self.sum
            .iter()
            .zip(&self.count)
            .map(|(s, &n)| {
                if n == 0 {
                    [0.0; 3]
                } else {
                    s.map(|v| (v / n as f64) as f32)
                }
            })
            .collect()
    }

    /// Per-pixel variance of the mean: s² / n with the unbiased sample
    /// variance s²; 0 where fewer than two samples exist.
    pub fn variance_of_mean(&self) -> Vec<[f32; 3]> {
        (0..self.sum.len())
            .map(|i| {
                let n = self.count[i] as f64;
                if n < 2.0 {
                    return [0.0; 3];
                }
                std::array::from_fn(|c| {
                    let m = self.sum[i][c] / n;
                    let s2 = ((self.sum_sq[i][c] - n * m * m) / (n - 1.0)).max(0.0);
                    (s2 / n) as f32
                })
            })
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

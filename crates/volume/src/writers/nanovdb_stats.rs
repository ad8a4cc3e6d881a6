//! Per-node statistics as NanoVDB stores them (`util/GridStats.h`): the
//! active values' minimum and maximum, mean and standard deviation
//! (population), and the inclusive index box of the active values. A
//! node's statistics combine its children's and its active tiles' (a tile
//! counts once per voxel it covers), with the pairwise update of the mean
//! and of the sum of squared deviations that NanoVDB uses, in `f64`.

/// Running statistics of active values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stats {
    pub(crate) count: u64,
    pub(crate) min: f32,
    pub(crate) max: f32,
    mean: f64,
    /// Sum of squared deviations from the mean.
    m2: f64,
    pub(crate) lo: [i32; 3],
    pub(crate) hi: [i32; 3],
}

impl Default for Stats {
    fn default() -> Self {
        Stats {
            count: 0,
            min: f32::MAX,
            max: f32::MIN,
            mean: 0.0,
            m2: 0.0,
            lo: [i32::MAX; 3],
            hi: [i32::MIN; 3],
        }
    }
}

impl Stats {
    /// One active voxel at `p`.
    pub(crate) fn voxel(&mut self, v: f32, p: [i32; 3]) {
        self.tile(v, 1, p, p);
    }

    /// `n` active voxels of value `v` filling the box `[lo, hi]`.
    pub(crate) fn tile(&mut self, v: f32, n: u64, lo: [i32; 3], hi: [i32; 3]) {
        self.min = self.min.min(v);
        self.max = self.max.max(v);
        let total = (self.count + n) as f64;
        let delta = v as f64 - self.mean;
        self.mean += delta * n as f64 / total;
        self.m2 += delta * delta * self.count as f64 * n as f64 / total;
        self.count += n;
        self.grow(lo, hi);
    }

    /// Merges a child's statistics.
    pub(crate) fn merge(&mut self, o: &Stats) {
        if o.count == 0 {
            return;
        }
        let total = (self.count + o.count) as f64;
        let delta = o.mean - self.mean;
        self.mean += delta * o.count as f64 / total;
        self.m2 += o.m2 + delta * delta * self.count as f64 * o.count as f64 / total;
        self.count += o.count;
        self.min = self.min.min(o.min);
        self.max = self.max.max(o.max);
        self.grow(o.lo, o.hi);
    }

    fn grow(&mut self, lo: [i32; 3], hi: [i32; 3]) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(lo[k]);
            self.hi[k] = self.hi[k].max(hi[k]);
        }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Minimum, maximum, mean and standard deviation as stored (zeros for
    /// a node without active values).
    pub(crate) fn stored(&self) -> [f32; 4] {
        if self.is_empty() {
            return [0.0; 4];
        }
        let var = self.m2 / self.count as f64;
        [
            self.min,
            self.max,
            self.mean as f32,
            var.max(0.0).sqrt() as f32,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merged_stats_equal_direct_ones() {
        let values = [0.5f32, 2.0, -1.0, 4.0, 4.0, 0.25];
        let mut all = Stats::default();
        let (mut a, mut b) = (Stats::default(), Stats::default());
        for (i, &v) in values.iter().enumerate() {
            let p = [i as i32, 0, -(i as i32)];
            all.voxel(v, p);
            if i < 2 { &mut a } else { &mut b }.voxel(v, p);
        }
        a.merge(&b);
        let mean = values.iter().sum::<f32>() as f64 / 6.0;
        let var = values
            .iter()
            .map(|&v| (v as f64 - mean).powi(2))
            .sum::<f64>()
            / 6.0;
        for s in [all, a] {
            let [min, max, avg, std] = s.stored();
            assert_eq!((min, max), (-1.0, 4.0));
            assert!((avg as f64 - mean).abs() < 1e-6 && (std as f64 - var.sqrt()).abs() < 1e-6);
            assert_eq!((s.lo, s.hi), ([0, 0, -5], [5, 0, 0]));
        }
        let mut t = Stats::default();
        t.tile(2.0, 8, [0; 3], [1; 3]);
        assert_eq!(t.stored(), [2.0, 2.0, 2.0, 0.0]);
    }
}

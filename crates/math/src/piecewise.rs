//! Piecewise-linear functions of one variable: the transfer functions of
//! scientific visualisation (ParaView's `vtkPiecewiseFunction` for opacity
//! and `vtkColorTransferFunction` in RGB, both with linear segments), with
//! `N` output channels. Outside the first and last point the function is
//! clamped (ParaView's default). Two points at the same `x` make a step,
//! right-continuous: the value at `x` is the second point's.

/// A piecewise-linear map from `f32` to `[f32; N]`.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear<const N: usize> {
    xs: Vec<f32>,
    ys: Vec<[f32; N]>,
    /// Bound on the rounding error of one evaluation (a few ulps of the
    /// largest value), by which [`Self::range_over`] widens its bounds.
    slack: f32,
    /// Smallest and largest first-channel value: no evaluation leaves them.
    extent: (f32, f32),
}

impl<const N: usize> PiecewiseLinear<N> {
    /// At least one point, every coordinate finite, `x` non-decreasing.
    pub fn new(points: Vec<(f32, [f32; N])>) -> Result<Self, String> {
        if points.is_empty() {
            return Err("needs at least one point".into());
        }
        for (i, (x, y)) in points.iter().enumerate() {
            if !x.is_finite() || y.iter().any(|v| !v.is_finite()) {
                return Err(format!("point {i} is not finite"));
            }
            if i > 0 && *x < points[i - 1].0 {
                return Err(format!(
                    "points must be sorted by value: point {i} ({x}) comes after {}",
                    points[i - 1].0
                ));
            }
        }
        let (xs, ys): (Vec<f32>, Vec<[f32; N]>) = points.into_iter().unzip();
        let largest = ys.iter().flatten().fold(0.0f32, |m, v| m.max(v.abs()));
        let extent = extent(&ys);
        Ok(PiecewiseLinear {
            xs,
            ys,
            slack: 4.0 * f32::EPSILON * largest,
            extent,
        })
    }

    /// A constant function.
    pub fn constant(y: [f32; N]) -> Self {
        PiecewiseLinear {
            xs: vec![0.0],
            extent: extent(&[y]),
            ys: vec![y],
            slack: 0.0,
        }
    }

    pub fn points(&self) -> impl Iterator<Item = (f32, [f32; N])> + '_ {
        self.xs.iter().copied().zip(self.ys.iter().copied())
    }

    pub fn len(&self) -> usize {
        self.xs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.xs.is_empty()
    }

    /// The same function of `x' = a·x + b` (`a > 0`): points move, values stay.
    pub fn remapped(&self, a: f32, b: f32) -> Self {
        PiecewiseLinear {
            xs: self.xs.iter().map(|x| a * x + b).collect(),
            ys: self.ys.clone(),
            slack: self.slack,
            extent: self.extent,
        }
    }

    /// The value at `x`. The result of each segment is clamped to its two
    /// end values, so a bound computed from the points ([`Self::range_over`])
    /// holds for every evaluation despite rounding. NaN maps to the first
    /// point's value.
    #[inline]
    pub fn eval(&self, x: f32) -> [f32; N] {
        let i = self.xs.partition_point(|&p| p <= x);
        if i == 0 {
            return self.ys[0];
        }
        if i == self.xs.len() {
            return self.ys[i - 1];
        }
        // xs[i − 1] ≤ x < xs[i], so the segment has positive width.
        let (x0, x1) = (self.xs[i - 1], self.xs[i]);
        let t = (x - x0) / (x1 - x0);
        let (a, b) = (self.ys[i - 1], self.ys[i]);
        std::array::from_fn(|c| (a[c] + t * (b[c] - a[c])).clamp(a[c].min(b[c]), a[c].max(b[c])))
    }
}

impl PiecewiseLinear<1> {
    /// (min, max) of the function over `[lo, hi]`: a linear segment takes
    /// its extrema at its ends, so the values at `lo`, `hi` and every point
    /// in between bound it; widened by a few ulps, because the rounded
    /// evaluation inside the segment through `lo` may pass the rounded value
    /// at `lo` (the bounds are majorants: they must hold for every lookup).
    /// NaN bounds give the range over all x.
    pub fn range_over(&self, lo: f32, hi: f32) -> (f32, f32) {
        let (lo, hi) = if lo <= hi {
            (lo, hi)
        } else if hi < lo {
            (hi, lo)
        } else {
            (f32::NEG_INFINITY, f32::INFINITY)
        };
        let (mut min, mut max) = (f32::INFINITY, f32::NEG_INFINITY);
        let first = self.xs.partition_point(|&p| p < lo);
        let last = self.xs.partition_point(|&p| p <= hi);
        let inner = self.ys[first..last].iter().map(|y| y[0]);
        for v in inner.chain([self.eval(lo)[0], self.eval(hi)[0]]) {
            min = min.min(v);
            max = max.max(v);
        }
        // Each segment's result is clamped to its end values, so no
        // evaluation leaves the points' extent.
        (
            (min - self.slack).max(self.extent.0),
            (max + self.slack).min(self.extent.1),
        )
    }
}

fn extent<const N: usize>(ys: &[[f32; N]]) -> (f32, f32) {
    ys.iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), y| {
            (lo.min(y[0]), hi.max(y[0]))
        })
}

#[cfg(test)]
mod piecewise_test {
    use super::*;
    use crate::Pcg32;

    fn f(points: &[(f32, f32)]) -> PiecewiseLinear<1> {
        PiecewiseLinear::new(points.iter().map(|&(x, y)| (x, [y])).collect()).unwrap()
    }

    #[test]
    fn interpolates_clamps_and_steps() {
        let g = f(&[(0.0, 0.0), (1.0, 2.0), (1.0, 5.0), (3.0, 1.0)]);
        assert_eq!(g.eval(-4.0), [0.0]);
        assert_eq!(g.eval(0.5), [1.0]);
        assert_eq!(g.eval(0.999_999), [1.999_998]);
        // Right-continuous step.
        assert_eq!(g.eval(1.0), [5.0]);
        assert_eq!(g.eval(2.0), [3.0]);
        assert_eq!(g.eval(9.0), [1.0]);
        assert_eq!(g.eval(f32::NAN), [0.0]);
        let rgb =
            PiecewiseLinear::new(vec![(0.0, [0.0, 1.0, 0.5]), (2.0, [1.0, 0.0, 0.5])]).unwrap();
        assert_eq!(rgb.eval(0.5), [0.25, 0.75, 0.5]);
    }

    #[test]
    fn bad_points_are_refused() {
        assert!(PiecewiseLinear::<1>::new(vec![]).is_err());
        assert!(PiecewiseLinear::new(vec![(1.0, [0.0]), (0.5, [1.0])]).is_err());
        assert!(PiecewiseLinear::new(vec![(f32::NAN, [0.0])]).is_err());
        assert!(PiecewiseLinear::new(vec![(0.0, [f32::INFINITY])]).is_err());
    }

    #[test]
    fn range_over_bounds_every_evaluation_and_is_attained() {
        let mut rng = Pcg32::new(4, 1);
        for _ in 0..200 {
            let n = 1 + rng.next_u32() as usize % 7;
            let mut xs: Vec<f32> = (0..n).map(|_| rng.next_f32() * 10.0 - 5.0).collect();
            xs.sort_by(f32::total_cmp);
            if n > 2 && rng.next_u32().is_multiple_of(3) {
                xs[1] = xs[2]; // a step
            }
            let g = f(&xs
                .iter()
                .map(|&x| (x, rng.next_f32() * 3.0 - 1.0))
                .collect::<Vec<_>>());
            let a = rng.next_f32() * 14.0 - 7.0;
            let b = a + rng.next_f32() * 6.0;
            let (lo, hi) = g.range_over(a, b);
            let (mut seen_lo, mut seen_hi) = (f32::INFINITY, f32::NEG_INFINITY);
            let knots = xs.iter().copied().filter(|x| (a..=b).contains(x));
            for x in (0..=4000)
                .map(|k| a + (b - a) * k as f32 / 4000.0)
                .chain(knots)
            {
                let v = g.eval(x)[0];
                assert!(v >= lo && v <= hi, "{v} outside [{lo}, {hi}] on [{a}, {b}]");
                seen_lo = seen_lo.min(v);
                seen_hi = seen_hi.max(v);
            }
            // Tight up to a step's left value, which x ≥ its point never sees.
            let has_step = xs.windows(2).any(|w| w[0] == w[1]);
            if !has_step {
                assert!(
                    (seen_hi - hi).abs() < 2e-3 && (seen_lo - lo).abs() < 2e-3,
                    "{xs:?} on [{a}, {b}]: seen [{seen_lo}, {seen_hi}], bound [{lo}, {hi}]"
                );
            }
        }
        let g = f(&[(0.0, 0.0), (1.0, 1.0)]);
        assert_eq!(g.range_over(f32::NAN, 0.5), (0.0, 1.0));
        let (lo, hi) = g.range_over(0.75, 0.25);
        assert!((lo - 0.25).abs() < 1e-6 && (hi - 0.75).abs() < 1e-6);
    }

    #[test]
    fn remapping_moves_points_not_values() {
        let g = f(&[(-1000.0, 0.0), (1000.0, 1.0)]);
        let h = g.remapped(1.0 / 2000.0, 0.5);
        assert_eq!(h.eval(0.75), g.eval(500.0));
    }
}

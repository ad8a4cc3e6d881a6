//! Russian roulette on the running weight of a tracking estimator:
//! ratio tracking multiplies its weight by 1 − σ_t/σ̄ at every
//! tentative collision, so in a dense medium it keeps reading the grid long
//! after the weight has become negligible — its cost grows with the
//! majorant's optical depth without bound. pbrt-v4 and Mitsuba 3 play
//! roulette once the weight is small; so does this: below `threshold` the
//! walk goes on with probability q = weight / threshold and its weights are
//! divided by q (the largest becomes the threshold), else it ends with
//! weight 0. E[weight after] = q · weight / q = weight: unbiased, and a
//! walk in a dense medium ends after a few collisions more.

use fogbank_math::Pcg32;

/// The threshold ratio and residual ratio tracking use unless told
/// otherwise (`roulette = 0` turns it off). Chosen by measurement
/// (`docs/results/roulette/README.md`, "Choosing the default"): across σ_t
/// scales 1 … 10⁶ it keeps both trackers' cost at or below track-length's
/// while raising their variance by a few per cent at most.
pub const DEFAULT_ROULETTE: f32 = 0.03;

/// Plays roulette on the weights `w` (one per colour channel) whose
/// running estimates are `scale[c] · w[c]` (residual ratio tracking:
/// exp(−k_c τ_c) of the control so far; 1 otherwise), on the largest.
/// Returns whether the walk goes on; `threshold` ≤ 0 never plays.
#[inline]
pub fn roulette<const N: usize>(
    w: &mut [f32; N],
    scale: [f32; N],
    threshold: f32,
    rng: &mut Pcg32,
) -> bool {
    if threshold <= 0.0 {
        return true;
    }
    let largest = (w.iter().zip(scale)).fold(0.0f32, |m, (x, s)| m.max((x * s).abs()));
    if largest >= threshold {
        return true;
    }
    let q = largest / threshold;
    if q > 0.0 && rng.next_f32() < q {
        w.iter_mut().for_each(|x| *x /= q);
        true
    } else {
        *w = [0.0; N];
        false
    }
}

#[cfg(test)]
mod roulette_test {
    use super::*;

    #[test]
    fn keeps_the_mean_and_bounds_the_weight() {
        let mut rng = Pcg32::new(4, 2);
        let (n, w0) = (200_000, [0.02f32, 0.05, -0.01]);
        let mut sum = [0.0f64; 3];
        let mut survived = 0;
        for _ in 0..n {
            let mut w = w0;
            if roulette(&mut w, [1.0; 3], 0.1, &mut rng) {
                survived += 1;
                assert!((w[1] - 0.1).abs() < 1e-6, "{w:?}");
            }
            for c in 0..3 {
                sum[c] += w[c] as f64;
            }
        }
        // Survival q = 0.5; each channel's mean is its weight (σ of the
        // mean: |w|/√n ≈ 1.1e-4 for 0.05).
        assert!((survived as f64 / n as f64 - 0.5).abs() < 0.005);
        for c in 0..3 {
            let mean = sum[c] / n as f64;
            assert!(
                (mean - w0[c] as f64).abs() < 5.0 * 0.05 / (n as f64).sqrt(),
                "{c}: {mean}"
            );
        }
        let mut w = [0.5f32];
        assert!(roulette(&mut w, [1.0], 0.1, &mut rng) && w == [0.5]);
        assert!(roulette(&mut w, [1.0], 0.0, &mut rng) && w == [0.5]);
        // The scale counts: 0.5 · 0.1 is below the threshold.
        let mut hits = 0;
        for _ in 0..1000 {
            let mut w = [0.5f32];
            hits += roulette(&mut w, [0.1], 0.1, &mut rng) as u32;
        }
        assert!((400..600).contains(&hits), "{hits}");
    }
}

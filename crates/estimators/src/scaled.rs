//! Transmittance of several extinctions k_c · σ_t from one walk (chromatic
//! media with one density): the estimators that combine
//! optical-depth estimates taken at positions that do not depend on the
//! extinction's scale — regular tracking and the analytic trilinear
//! integral (exact τ), ray marching, the jackknife at a fixed sample count
//! (its importance and step F/N scale with σ_t, so the positions stay) —
//! estimate every channel's τ as k_c times the walk's, with no extra
//! lookups. Ratio tracking and residual ratio tracking weight every channel
//! at the largest channel's tentative collisions (its majorant bounds
//! k_c σ_t for k_c ≤ 1; the residual's control scales with k_c): unbiased
//! per channel, though not the walks each channel would take alone.
//! Track-length (a binary outcome of one channel), Kettunen's power series
//! and the jackknife at a fixed step return `None` (the caller walks each
//! channel).

use crate::estimator::{
    AnalyticTrilinear, Jackknife, RatioTracking, RayMarching, RegularTracking,
    ResidualRatioTracking,
};
use crate::jackknife::{jackknife_transmittance, optical_depths, Sampling, StepMode};
use crate::{analytic_trilinear, ratio_tracking, ray_marching, regular_tracking};
use crate::{residual_ratio_tracking, Estimator};
use fogbank_math::{Pcg32, Ray, RaySegment};
use fogbank_volume::{Medium, MediumView};

/// The optical-depth estimates one walk gives, and how an estimator turns
/// them into a transmittance.
enum Depths {
    /// exp(−τ) of one estimate (exact or marched).
    Exp(f64),
    /// Peters 2025, Eq. 4 of two interleaved estimates.
    Jackknife([f64; 2]),
}

/// Per channel c, the transmittance of `medium` with its extinction times
/// `k[c]` along the world ray over `[0, t_max]`, and the lookups of the one
/// walk; `None` when `e` cannot share a walk between scales.
pub fn transmittance_scaled(
    e: Estimator,
    medium: &Medium,
    world: &Ray,
    t_max: f32,
    rng: &mut Pcg32,
    k: [f32; 3],
) -> Option<([f32; 3], u32)> {
    let Some((r, t0, t1)) = medium.to_index(world, 0.0, t_max) else {
        return Some(([1.0; 3], 0));
    };
    let seg = RaySegment::new(r, t0, t1);
    let view = medium.view();
    let (depths, lookups) = match e {
        Estimator::RegularTracking(RegularTracking) => match view {
            MediumView::F16(v) => exp(regular_tracking::optical_depth(&v, &seg)),
            MediumView::F32(v) => exp(regular_tracking::optical_depth(&v, &seg)),
            MediumView::Analytic(_) => return None,
        },
        Estimator::AnalyticTrilinear(AnalyticTrilinear) => match view {
            MediumView::F16(v) => exp(analytic_trilinear::optical_depth(&v, &seg)),
            MediumView::F32(v) => exp(analytic_trilinear::optical_depth(&v, &seg)),
            MediumView::Analytic(_) => return None,
        },
        Estimator::RayMarching(RayMarching { samples, clip }) => with_view!(view, v => exp(
            ray_marching::optical_depth(&v, &seg, samples, clip, rng)
        )),
        Estimator::Jackknife(Jackknife {
            samples,
            mode: StepMode::FixedCount,
            jitter,
        }) => {
            let (mut lookups, mut x) = (0, [0.0; 2]);
            let sampling = Sampling::fixed_count(samples, jitter);
            with_view!(view, v => optical_depths(
                &v, &seg, sampling, rng, &mut lookups, &mut x
            ));
            (Depths::Jackknife(x), lookups)
        }
        Estimator::RatioTracking(RatioTracking { roulette }) => {
            return Some(with_view!(view, v => ratio_tracking::transmittance_scaled(
                &v, &seg, rng, k, roulette
            )))
        }
        Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette }) => {
            return Some(
                with_view!(view, v => residual_ratio_tracking::transmittance_scaled(
                    &v, &seg, rng, k, roulette
                )),
            )
        }
        _ => return None,
    };
    let t = k.map(|k| {
        let k = k as f64;
        match depths {
            Depths::Exp(tau) => (-(k * tau)).exp() as f32,
            Depths::Jackknife([x0, x1]) => jackknife_transmittance(k * x0, k * x1) as f32,
        }
    });
    Some((t, lookups))
}

fn exp((tau, lookups): (f64, u32)) -> (Depths, u32) {
    (Depths::Exp(tau), lookups)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimator::TrackLength;
    use crate::optical_depth::Jitter;
    use crate::transmittance;
    use fogbank_math::Vec3;
    use fogbank_volume::{BrickGrid, DensityData, Filter, Precision};

    fn medium(scale: f32) -> Medium {
        let g = BrickGrid::from_fn([16, 16, 16], |i, j, l| {
            ((i as f32 * 0.7).sin() + (j as f32 * 0.3).cos() + l as f32 * 0.05 + 2.0) * 0.5
        })
        .unwrap();
        let data = DensityData::from_f32(g, Precision::F32);
        Medium::new(data, scale, Filter::Trilinear, Default::default(), 4)
    }

    /// Each channel of the shared walk equals the estimator run on the
    /// medium with scale k_c · s from the same random stream.
    #[test]
    fn one_walk_equals_each_scaled_medium() {
        let s = 1.3;
        let k = [0.25, 0.6, 1.0];
        let ray = Ray::new(
            Vec3::new(-1.0, 3.1, 5.2),
            Vec3::new(1.0, 0.21, 0.13).normalize(),
        );
        let jitter = Jitter::Stratified;
        for e in [
            Estimator::RegularTracking(RegularTracking),
            Estimator::AnalyticTrilinear(AnalyticTrilinear),
            Estimator::RayMarching(RayMarching {
                samples: 7,
                clip: true,
            }),
            Estimator::Jackknife(Jackknife {
                samples: 5,
                mode: StepMode::FixedCount,
                jitter,
            }),
        ] {
            for seed in 0..20 {
                let (t, n) =
                    transmittance_scaled(e, &medium(s), &ray, 40.0, &mut Pcg32::new(seed, 1), k)
                        .unwrap();
                assert!(
                    n > 0 || e == Estimator::AnalyticTrilinear(AnalyticTrilinear),
                    "{e:?}"
                );
                for c in 0..3 {
                    let one =
                        transmittance(e, &medium(s * k[c]), &ray, 40.0, &mut Pcg32::new(seed, 1));
                    assert!(
                        (one.transmittance - t[c]).abs() <= 2e-5,
                        "{e:?} seed {seed} channel {c}: {} vs {}",
                        t[c],
                        one.transmittance
                    );
                    assert_eq!(one.lookups, n, "{e:?}");
                }
            }
        }
        let tracking = Estimator::TrackLength(TrackLength);
        assert!(
            transmittance_scaled(tracking, &medium(s), &ray, 40.0, &mut Pcg32::new(1, 1), k)
                .is_none()
        );
    }

    /// Ratio tracking and residual ratio tracking share the largest
    /// channel's walk: each channel's mean is that channel's exact T.
    #[test]
    fn shared_tracking_walks_are_unbiased_per_channel() {
        let m = medium(0.05);
        let k = [0.2, 0.55, 1.0];
        let ray = Ray::new(
            Vec3::new(-1.0, 3.1, 5.2),
            Vec3::new(1.0, 0.21, 0.13).normalize(),
        );
        let exact = transmittance_scaled(
            Estimator::RegularTracking(RegularTracking),
            &m,
            &ray,
            40.0,
            &mut Pcg32::new(0, 0),
            k,
        )
        .unwrap()
        .0;
        assert!(exact[2] > 0.02 && exact[2] < 0.9, "{exact:?}");
        for e in [
            Estimator::RatioTracking(RatioTracking { roulette: 0.0 }),
            Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette: 0.0 }),
            Estimator::RatioTracking(RatioTracking { roulette: 0.5 }),
            Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette: 0.5 }),
        ] {
            let n = 20_000;
            let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
            let mut rng = Pcg32::new(9, 3);
            for _ in 0..n {
                let (t, _) = transmittance_scaled(e, &m, &ray, 40.0, &mut rng, k).unwrap();
                for c in 0..3 {
                    sum[c] += t[c] as f64;
                    sum2[c] += (t[c] as f64).powi(2);
                }
            }
            for c in 0..3 {
                let mean = sum[c] / n as f64;
                let se = ((sum2[c] / n as f64 - mean * mean) / n as f64).sqrt();
                let d = (mean - exact[c] as f64).abs();
                assert!(
                    d < 4.0 * se + 1e-6,
                    "{e:?} channel {c}: {mean} ± {se} vs {}",
                    exact[c]
                );
            }
        }
    }
}

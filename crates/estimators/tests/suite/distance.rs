//! Distance samplers against exact densities: the empirical CDF of sampled
//! collision distances must match 1 − T(x) at several x within 4 binomial
//! standard errors, and escapes must happen with probability T(t1).
//! (Bin-wise chi-square tests with the shared harness come with it.)

use crate::support;
use fogbank_estimators::estimator::{AnalyticTrilinear, RegularTracking};

use fogbank_estimators::distance::{
    decomposition_tracking, delta_tracking, equiangular, regular_tracking, FreeFlight,
};
use fogbank_estimators::{transmittance, Estimator};
use fogbank_math::{Pcg32, Ray, RaySegment, SampleKey, Vec3};
use fogbank_volume::{Filter, Medium, MediumView};
use support::*;

#[derive(Clone, Copy, Debug)]
enum Sampler {
    Delta,
    Decomposition,
    Regular,
}

fn draw(s: Sampler, m: &Medium, ray: &Ray, rng: &mut Pcg32) -> FreeFlight {
    let (r, t0, t1) = m.to_index(ray, 0.0, f32::INFINITY).unwrap();
    match (m.view(), s) {
        (MediumView::F32(v), Sampler::Delta) => {
            delta_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::F32(v), Sampler::Decomposition) => {
            decomposition_tracking::sample(&v, &RaySegment::new(r, t0, t1), rng)
        }
        (MediumView::F32(v), Sampler::Regular) => {
            regular_tracking::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng).free_flight()
        }
        _ => unreachable!("tests use f32 grids"),
    }
}

fn check_cdf(s: Sampler, m: &Medium, ray: &Ray, exact: Estimator, label: &str) {
    let n = 100_000u32;
    let ts: Vec<Option<f32>> = (0..n)
        .map(|i| {
            draw(
                s,
                m,
                ray,
                &mut SampleKey {
                    seed: 4,
                    pixel: 0,
                    sample: i,
                    dimension: 0,
                }
                .rng(),
            )
            .t
        })
        .collect();
    let (_, t0, t1) = m.to_index(ray, 0.0, f32::INFINITY).unwrap();
    for k in 1..=8 {
        let x = t0 + (t1 - t0) * k as f32 / 8.0;
        // P(collision before x) = 1 − T(0, x).
        let tx = transmittance(exact, m, ray, x, &mut Pcg32::new(0, 0)).transmittance as f64;
        let p = 1.0 - tx;
        let f = ts.iter().filter(|t| t.is_some_and(|t| t < x)).count() as f64 / n as f64;
        let se = (p * (1.0 - p) / n as f64).sqrt().max(1e-6);
        assert!(
            (f - p).abs() < 4.0 * se,
            "{s:?} on {label}: P(t < {x}) = {f}, exact {p} (se {se})"
        );
    }
    let escaped = ts.iter().filter(|t| t.is_none()).count() as f64 / n as f64;
    let t_all =
        transmittance(exact, m, ray, f32::INFINITY, &mut Pcg32::new(0, 0)).transmittance as f64;
    let se = (t_all * (1.0 - t_all) / n as f64).sqrt().max(1e-6);
    assert!(
        (escaped - t_all).abs() < 4.0 * se,
        "{s:?} on {label}: escape {escaped} vs T {t_all}"
    );
}

#[test]
fn free_flight_samplers_match_one_minus_transmittance() {
    let grid = cloud(32, 11);
    let ray = Ray::new(
        Vec3::new(-4.0, 14.0, 15.0),
        Vec3::new(1.0, 0.05, 0.02).normalize(),
    );
    for (filter, exact) in [
        (Filter::Nearest, Estimator::RegularTracking(RegularTracking)),
        (
            Filter::StochasticTrilinear,
            Estimator::AnalyticTrilinear(AnalyticTrilinear),
        ),
    ] {
        let m = grid_medium(grid.clone(), filter, 0.15, 8);
        for s in [Sampler::Delta, Sampler::Decomposition] {
            check_cdf(s, &m, &ray, exact, filter.name());
        }
    }
    let m = grid_medium(grid, Filter::Nearest, 0.15, 8);
    check_cdf(
        Sampler::Regular,
        &m,
        &ray,
        Estimator::RegularTracking(RegularTracking),
        "nearest",
    );
}

#[test]
fn equiangular_pdf_normalises_and_matches_its_samples() {
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    let light = Vec3::new(3.0, 0.5, 0.2);
    let (a, b) = (0.5f32, 7.0f32);
    // ∫ pdf = 1 by midpoint quadrature.
    let m = 200_000;
    let h = (b - a) as f64 / m as f64;
    let integral: f64 = (0..m)
        .map(|i| equiangular::pdf(&ray, light, a, b, a + ((i as f64 + 0.5) * h) as f32) as f64 * h)
        .sum();
    assert!((integral - 1.0).abs() < 1e-3, "{integral}");
    // Empirical CDF of samples vs the integrated pdf; each sample's pdf is pdf(t).
    let mut rng = Pcg32::new(1, 1);
    let n = 200_000;
    let ts: Vec<f32> = (0..n)
        .map(|_| {
            let (t, p) = equiangular::sample(&ray, light, a, b, rng.next_f32());
            assert!((p - equiangular::pdf(&ray, light, a, b, t)).abs() <= 1e-4 * p.max(1.0));
            t
        })
        .collect();
    for k in 1..8 {
        let x = a + (b - a) * k as f32 / 8.0;
        let steps = ((x - a) as f64 / h) as usize;
        let p: f64 = (0..steps)
            .map(|i| {
                equiangular::pdf(&ray, light, a, b, a + ((i as f64 + 0.5) * h) as f32) as f64 * h
            })
            .sum();
        let f = ts.iter().filter(|&&t| t < x).count() as f64 / n as f64;
        let se = (p * (1.0 - p) / n as f64).sqrt();
        assert!((f - p).abs() < 4.0 * se + 1e-3, "P(t < {x}) = {f} vs {p}");
    }
}

/// Chi-square of sampled collision distances against the exact density
/// σ_t(t)·T(t) on a piecewise-constant (nearest) medium, escape as its own bin.
#[test]
fn free_flight_samplers_pass_chi_square() {
    use fogbank_math::chi2::{sidak, IntervalTest};
    let grid = cloud(32, 11);
    let m = grid_medium(grid, Filter::Nearest, 0.15, 8);
    let ray = Ray::new(Vec3::new(-4.0, 14.5, 15.5), Vec3::X);
    let (r, t0, t1) = m.to_index(&ray, 0.0, f32::INFINITY).unwrap();
    let MediumView::F32(v) = m.view() else {
        unreachable!()
    };
    let density = |t: f64| -> f64 {
        let t = t as f32;
        if t < t0 || t > t1 {
            return 0.0;
        }
        let p = r.at(t);
        let sigma_t = v.scale as f64 * v.grid.nearest(p) as f64;
        let tr = transmittance(
            Estimator::RegularTracking(RegularTracking),
            &m,
            &ray,
            t,
            &mut Pcg32::new(0, 0),
        )
        .transmittance as f64;
        sigma_t * tr
    };
    let escape = transmittance(
        Estimator::RegularTracking(RegularTracking),
        &m,
        &ray,
        f32::INFINITY,
        &mut Pcg32::new(0, 0),
    )
    .transmittance as f64;
    let samplers = [Sampler::Delta, Sampler::Decomposition, Sampler::Regular];
    let alpha = sidak(0.01, samplers.len() as u32);
    for s in samplers {
        let test = IntervalTest {
            a: t0 as f64,
            b: t1 as f64,
            bins: 48,
            samples: 200_000,
            seed: 9,
        };
        let result = test.run(
            |rng| draw(s, &m, &ray, rng).t.map(|t| t as f64),
            density,
            escape,
        );
        assert!(result.passes(alpha), "{s:?}: {result}");
    }
}

#[test]
fn equiangular_passes_chi_square() {
    use fogbank_math::chi2::IntervalTest;
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    let light = Vec3::new(3.0, 0.5, 0.2);
    let (a, b) = (0.5f32, 7.0f32);
    let test = IntervalTest {
        a: a as f64,
        b: b as f64,
        bins: 64,
        samples: 200_000,
        seed: 3,
    };
    let result = test.run(
        |rng| Some(equiangular::sample(&ray, light, a, b, rng.next_f32()).0 as f64),
        |t| equiangular::pdf(&ray, light, a, b, t as f32) as f64,
        0.0,
    );
    assert!(result.passes(0.01), "{result}");
}

/// Chi-square of exact free-flight sampling through the trilinear field:
/// density σ_t(t)·T(t) of the trilinear interpolant (T by the analytic
/// trilinear optical depth), escape as its own bin; a power check: the same
/// samples fail against the nearest-filtered density.
#[test]
fn analytic_trilinear_sampling_passes_chi_square() {
    use fogbank_estimators::distance::analytic_trilinear;
    use fogbank_math::chi2::IntervalTest;
    use fogbank_volume::VolumeAccess;
    let grid = cloud(32, 11);
    let m = grid_medium(grid, Filter::Trilinear, 0.15, 8);
    let ray = Ray::new(
        Vec3::new(-4.0, 14.3, 15.6),
        Vec3::new(1.0, 0.02, -0.01).normalize(),
    );
    let (r, t0, t1) = m.to_index(&ray, 0.0, f32::INFINITY).unwrap();
    let MediumView::F32(v) = m.view() else {
        unreachable!()
    };
    let exact = |t: f32| {
        transmittance(
            Estimator::AnalyticTrilinear(AnalyticTrilinear),
            &m,
            &ray,
            t,
            &mut Pcg32::new(0, 0),
        )
        .transmittance as f64
    };
    let trilinear = |t: f64| -> f64 {
        let t = t as f32;
        if t < t0 || t > t1 {
            return 0.0;
        }
        v.sigma_t(r.at(t), Vec3::ZERO) as f64 * exact(t)
    };
    let nearest = |t: f64| -> f64 {
        let t = t as f32;
        if t < t0 || t > t1 {
            return 0.0;
        }
        v.scale as f64 * v.grid.nearest(r.at(t)) as f64 * exact(t)
    };
    let escape = exact(f32::INFINITY);
    assert!(escape > 0.05 && escape < 0.95, "escape {escape}");
    let test = IntervalTest {
        a: t0 as f64,
        b: t1 as f64,
        bins: 48,
        samples: 200_000,
        seed: 13,
    };
    let draw = |rng: &mut Pcg32| {
        analytic_trilinear::sample_tracked(&v, &RaySegment::new(r, t0, t1), rng)
            .free_flight()
            .t
            .map(|t| t as f64)
    };
    let result = test.run(draw, trilinear, escape);
    assert!(result.passes(0.01), "{result}");
    let wrong = test.run(draw, nearest, escape);
    assert!(
        !wrong.passes(0.01),
        "the nearest-filtered density should be rejected: {wrong}"
    );
}

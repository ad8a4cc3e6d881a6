//! Unbiased estimators: the mean over many fixed-seed estimates lies within
//! 4 standard errors (measured) of the exact transmittance, on analytic media
//! and a procedural cloud, for optical depths from 0.01 to 10.

use crate::support;
use fogbank_estimators::estimator::{
    AnalyticTrilinear, RatioTracking, RegularTracking, ResidualRatioTracking, TrackLength,
    UnbiasedRayMarching,
};

use fogbank_estimators::{transmittance, Estimator};
use fogbank_math::DAffine3;
use fogbank_math::{Pcg32, Ray, SampleKey, Vec3};
use fogbank_volume::{DensityData, Filter, Medium};
use support::*;

const TAUS: [f64; 5] = [0.01, 0.1, 1.0, 3.0, 10.0];

struct Stats {
    mean: f64,
    se: f64,
}

fn run(e: Estimator, m: &Medium, ray: &Ray, n: u32, seed: u32) -> Stats {
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for i in 0..n {
        let mut rng = SampleKey {
            seed,
            pixel: 0,
            sample: i,
            dimension: 0,
        }
        .rng();
        let t = transmittance(e, m, ray, f32::INFINITY, &mut rng).transmittance as f64;
        s += t;
        s2 += t * t;
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    Stats {
        mean,
        se: (var / n as f64).sqrt(),
    }
}

fn check(e: Estimator, m: &Medium, ray: &Ray, exact: f64, label: &str) {
    // Deep rays (T < 1e-3) are dominated by rare events (track-length hits,
    // large ratio-tracking weights under stochastic filtering): 10× samples.
    let n = if exact < 1e-3 { 400_000 } else { 20_000 };
    let st = run(e, m, ray, n, 17);
    // f32 arithmetic bounds how exact a zero-variance estimate can be.
    let tol = 4.0 * st.se + 1e-5 * exact;
    assert!(
        (st.mean - exact).abs() <= tol,
        "{} on {label}: mean {:.6e} exact {:.6e} (|diff| {:.3e} > 4 SE {:.3e})",
        e.name(),
        st.mean,
        exact,
        (st.mean - exact).abs(),
        tol
    );
}

fn rays_for(n: u32) -> Vec<(Ray, &'static str)> {
    let c = Vec3::splat(n as f32 * 0.5);
    vec![
        (
            Ray::new(
                Vec3::new(-1.0, 0.3, 0.45) * n as f32,
                (c - Vec3::new(-1.0, 0.3, 0.45) * n as f32).normalize(),
            ),
            "oblique",
        ),
        (
            Ray::new(
                c + Vec3::new(0.1, -0.05, 0.02) * n as f32,
                Vec3::new(0.3, 0.8, -0.52).normalize(),
            ),
            "inside",
        ),
        (
            Ray::new(Vec3::new(-5.0, 0.5 * n as f32, 0.37 * n as f32), Vec3::X),
            "axis",
        ),
    ]
}

fn unbiased_on_analytic_media(e: Estimator) {
    let n = 32;
    for field in analytic_media(n) {
        for (ray, rname) in rays_for(n) {
            let unit = Medium::new(
                DensityData::Analytic(field.clone()),
                1.0,
                Filter::Trilinear,
                DAffine3::IDENTITY,
                8,
            );
            let t1 = transmittance(
                Estimator::AnalyticTrilinear(AnalyticTrilinear),
                &unit,
                &ray,
                f32::INFINITY,
                &mut Pcg32::new(0, 0),
            )
            .transmittance as f64;
            let tau1 = -t1.ln();
            let targets: Vec<f64> = if tau1 <= 0.0 {
                vec![0.0]
            } else {
                TAUS.to_vec()
            };
            for target in targets {
                let scale = if tau1 > 0.0 {
                    (target / tau1) as f32
                } else {
                    1.0
                };
                let m = Medium::new(
                    DensityData::Analytic(field.clone()),
                    scale,
                    Filter::Trilinear,
                    DAffine3::IDENTITY,
                    8,
                );
                let exact = (-field.optical_depth(&ray, 0.0, f32::INFINITY) * scale as f64).exp();
                check(
                    e,
                    &m,
                    &ray,
                    exact,
                    &format!("{} {rname} τ={target}", field.name()),
                );
            }
        }
    }
}

fn unbiased_on_a_procedural_cloud(e: Estimator) {
    let n = 48;
    let grid = cloud(n, 3);
    for filter in [
        Filter::Nearest,
        Filter::Trilinear,
        Filter::StochasticTrilinear,
    ] {
        let reference = if filter == Filter::Nearest {
            Estimator::RegularTracking(RegularTracking)
        } else {
            Estimator::AnalyticTrilinear(AnalyticTrilinear)
        };
        for (ray, rname) in rays_for(n) {
            let unit = grid_medium(grid.clone(), filter, 1.0, 16);
            let t1 = transmittance(reference, &unit, &ray, f32::INFINITY, &mut Pcg32::new(0, 0))
                .transmittance as f64;
            let tau1 = -t1.ln();
            assert!(tau1 > 0.0, "ray {rname} misses the cloud");
            for target in TAUS {
                let scale = (target / tau1) as f32;
                let m = grid_medium(grid.clone(), filter, scale, 16);
                let exact = transmittance(reference, &m, &ray, f32::INFINITY, &mut Pcg32::new(0, 0))
                    .transmittance as f64;
                check(
                    e,
                    &m,
                    &ray,
                    exact,
                    &format!("cloud {} {rname} τ={target}", filter.name()),
                );
            }
        }
    }
}

#[test]
fn track_length_is_unbiased() {
    unbiased_on_analytic_media(Estimator::TrackLength(TrackLength));
    unbiased_on_a_procedural_cloud(Estimator::TrackLength(TrackLength));
}

#[test]
fn ratio_tracking_is_unbiased() {
    let e = Estimator::RatioTracking(RatioTracking { roulette: 0.0 });
    unbiased_on_analytic_media(e);
    unbiased_on_a_procedural_cloud(e);
}

#[test]
fn residual_ratio_tracking_is_unbiased() {
    let e = Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette: 0.0 });
    unbiased_on_analytic_media(e);
    unbiased_on_a_procedural_cloud(e);
}

/// What a user gets: both trackers with their default roulette.
#[test]
fn trackers_with_the_default_roulette_are_unbiased() {
    for name in ["ratio_tracking", "residual_ratio_tracking"] {
        let e = Estimator::parse(name).unwrap();
        assert_ne!(e, e.without_roulette(), "{name} plays roulette by default");
        unbiased_on_analytic_media(e);
        unbiased_on_a_procedural_cloud(e);
    }
}

/// Russian roulette on the running weight (a high threshold, so that most
/// walks play it; at τ = 10 every walk does) keeps both unbiased.
#[test]
fn tracking_with_roulette_is_unbiased() {
    for e in [
        Estimator::RatioTracking(RatioTracking { roulette: 0.3 }),
        Estimator::ResidualRatioTracking(ResidualRatioTracking { roulette: 0.3 }),
    ] {
        unbiased_on_analytic_media(e);
        unbiased_on_a_procedural_cloud(e);
    }
}

#[test]
fn unbiased_ray_marching_is_unbiased() {
    for mult in [1, 2] {
        let e = Estimator::UnbiasedRayMarching(UnbiasedRayMarching { mult });
        unbiased_on_analytic_media(e);
        unbiased_on_a_procedural_cloud(e);
    }
}

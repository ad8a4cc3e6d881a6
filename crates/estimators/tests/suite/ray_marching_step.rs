//! Hansen 2025's ray-marching baseline (§2.4): exact where σ_t is constant
//! (the in-step solve inverts an exponential), converging to the exact
//! optical depth as the step shrinks, and bounded on long segments.

use crate::support;

use fogbank_estimators::analytic_trilinear;
use fogbank_estimators::distance::ray_marching;
use fogbank_math::chi2::IntervalTest;
use fogbank_math::{Pcg32, Ray, RaySegment, Vec3};
use fogbank_volume::{BrickGrid, Filter, MediumView};
use support::*;

#[test]
fn constant_medium_is_sampled_exactly() {
    let m = grid_medium(
        BrickGrid::from_fn([8, 8, 8], |_, _, _| 1.0).unwrap(),
        Filter::Trilinear,
        0.3,
        4,
    );
    let MediumView::F32(v) = m.view() else {
        unreachable!()
    };
    let ray = Ray::new(Vec3::new(4.1, 3.7, -1.0), Vec3::Z);
    let (r, t0, t1) = m.to_index(&ray, 0.0, f32::INFINITY).unwrap();
    let sigma = 0.3f64;
    let len = (t1 - t0) as f64;
    for dt in [0.37f32, 3.0] {
        let test = IntervalTest {
            a: t0 as f64,
            b: t1 as f64,
            bins: 40,
            samples: 100_000,
            seed: 9,
        };
        let res = test.run(
            |rng| {
                ray_marching::sample(&v, &RaySegment::new(r, t0, t1), dt, rng)
                    .t
                    .map(|t| t as f64)
            },
            |x| sigma * (-sigma * (x - t0 as f64)).exp(),
            (-sigma * len).exp(),
        );
        assert!(res.passes(0.005), "step {dt}:\n{res}");
        let (t, _) =
            ray_marching::transmittance(&v, &RaySegment::new(r, t0, t1), dt, &mut Pcg32::new(1, 1));
        assert!(
            (t as f64 - (-sigma * len).exp()).abs() < 1e-6,
            "step {dt}: {t}"
        );
    }
}

#[test]
fn small_steps_converge_and_long_walks_are_bounded() {
    let m = grid_medium(cloud(32, 5), Filter::Trilinear, 0.3, 8);
    let MediumView::F32(v) = m.view() else {
        unreachable!()
    };
    let ray = Ray::new(
        Vec3::new(-3.0, 15.2, 16.7),
        Vec3::new(1.0, 0.05, -0.02).normalize(),
    );
    let (r, t0, t1) = m.to_index(&ray, 0.0, f32::INFINITY).unwrap();
    let exact = (-analytic_trilinear::optical_depth(&v, &RaySegment::new(r, t0, t1)).0).exp();
    let mut rng = Pcg32::new(2, 2);
    let mean = |dt: f32, rng: &mut Pcg32| -> f64 {
        (0..2000)
            .map(|_| ray_marching::transmittance(&v, &RaySegment::new(r, t0, t1), dt, rng).0 as f64)
            .sum::<f64>()
            / 2000.0
    };
    let fine = mean(0.05, &mut rng);
    assert!(
        (fine - exact).abs() < 2e-3 * exact.max(0.05),
        "{fine} vs {exact}"
    );
    // A step far below the segment: the walk is capped, not runaway.
    let (_, lookups) =
        ray_marching::transmittance(&v, &RaySegment::new(r, t0, t1), 1e-12, &mut rng);
    assert!(lookups <= ray_marching::MAX_STEPS, "{lookups}");
}

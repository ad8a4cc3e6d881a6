//! The reuse target's deterministic ray marching (Lin et al. 2021 §4.3): exact on a
//! constant field, the same bits on every call, and converging to the
//! analytic trilinear optical depth as the step shrinks.

use crate::support;

use fogbank_estimators::{analytic_trilinear, deterministic_marching};
use fogbank_math::{Ray, RaySegment, Vec3};
use fogbank_volume::{Filter, MediumView};
use support::*;

#[test]
fn deterministic_marching_is_exact_repeatable_and_converges() {
    // A constant field: τ = σ · length for any step.
    let constant = grid_medium(
        fogbank_volume::BrickGrid::from_fn([16, 16, 16], |_, _, _| 0.7).unwrap(),
        Filter::StochasticTrilinear,
        2.0,
        8,
    );
    let MediumView::F32(v) = constant.view() else {
        unreachable!()
    };
    let r = Ray::new(
        Vec3::new(-1.0, 3.3, 4.1),
        Vec3::new(1.0, 0.3, 0.2).normalize(),
    );
    let (_, t0, t1) = constant.to_index(&r, 0.0, f32::INFINITY).unwrap();
    let (tau, n) = deterministic_marching::optical_depth(&v, &RaySegment::new(r, t0, t1), 1.7);
    let exact = 1.4 * (t1 - t0) as f64;
    assert!((tau - exact).abs() < 1e-5 * exact, "{tau} vs {exact}");
    assert_eq!(n as f64, (((t1 - t0) / 1.7) as f64).ceil());

    // A cloud: repeatable to the bit, and converging to the exact τ.
    let m = grid_medium(cloud(32, 5), Filter::StochasticTrilinear, 0.2, 8);
    let MediumView::F32(v) = m.view() else {
        unreachable!()
    };
    let world = Ray::new(
        Vec3::new(-3.0, 15.2, 16.7),
        Vec3::new(1.0, 0.05, -0.02).normalize(),
    );
    let (r, t0, t1) = m.to_index(&world, 0.0, f32::INFINITY).unwrap();
    let (exact, _) = analytic_trilinear::optical_depth(&v, &RaySegment::new(r, t0, t1));
    assert!(exact > 0.5, "a ray through the cloud: τ = {exact}");
    let diagonal = 3f32.sqrt();
    let a = deterministic_marching::optical_depth(&v, &RaySegment::new(r, t0, t1), diagonal);
    let b = deterministic_marching::optical_depth(&v, &RaySegment::new(r, t0, t1), diagonal);
    assert_eq!(a.0.to_bits(), b.0.to_bits());
    let fine = deterministic_marching::optical_depth(&v, &RaySegment::new(r, t0, t1), 0.02).0;
    assert!((fine - exact).abs() < 1e-3 * exact, "{fine} vs {exact}");
    assert!(
        (a.0 - exact).abs() > (fine - exact).abs(),
        "coarser is no closer"
    );
}

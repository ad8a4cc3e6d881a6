//! The chi-square harness must accept correct samplers and reject subtly
//! wrong ones; otherwise the sampling tests built on it prove nothing.

use fogbank_math::chi2::{sidak, IntervalTest, SphereTest, SIGNIFICANCE};
use glam::DVec3;
use std::f64::consts::PI;

/// Tests in this file expected to pass share one 1 % false-alarm budget.
const PASSING_TESTS: u32 = 3;

fn alpha() -> f64 {
    sidak(SIGNIFICANCE, PASSING_TESTS)
}

fn uniform_sphere(u: [f64; 2]) -> DVec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

#[test]
fn exponential_distance_with_escape_passes() {
    // Free-flight distance in a homogeneous slab of thickness 1.5: photons
    // that fly past it escape, with probability e^(−σ·1.5).
    let sigma = 2.0;
    let b = 1.5;
    let test = IntervalTest {
        a: 0.0,
        b,
        bins: 50,
        samples: 200_000,
        seed: 1,
    };
    let r = test.run(
        |rng| {
            let t = -(1.0 - rng.next_f64()).ln() / sigma;
            (t <= b).then_some(t)
        },
        |t| sigma * (-sigma * t).exp(),
        (-sigma * b).exp(),
    );
    r.assert_passes(alpha(), 1e-9, "");
}

#[test]
fn tilted_interval_pdf_fails() {
    // Uniform samples judged against a pdf tilted by ±5 %.
    let test = IntervalTest {
        a: 0.0,
        b: 1.0,
        bins: 50,
        samples: 200_000,
        seed: 2,
    };
    let r = test.run(
        |rng| Some(rng.next_f64()),
        |x| 1.0 + 0.05 * (2.0 * x - 1.0),
        0.0,
    );
    println!("{r}");
    assert!((r.total_probability - 1.0).abs() < 1e-9);
    assert!(r.p_value < 1e-6, "{r}");
}

#[test]
fn wrong_escape_probability_fails() {
    let sigma = 2.0;
    let b = 1.5;
    let test = IntervalTest {
        a: 0.0,
        b,
        bins: 20,
        samples: 200_000,
        seed: 3,
    };
    // Claims 10 % more escapes than the sampler produces (pdf renormalised).
    let escape = (-sigma * b).exp();
    let claimed = 1.1 * escape;
    let r = test.run(
        |rng| {
            let t = -(1.0 - rng.next_f64()).ln() / sigma;
            (t <= b).then_some(t)
        },
        |t| sigma * (-sigma * t).exp() * (1.0 - claimed) / (1.0 - escape),
        claimed,
    );
    println!("{r}");
    assert!(r.p_value < 1e-3, "{r}");
}

#[test]
fn uniform_sphere_passes() {
    let test = SphereTest::new([20, 40], 400_000, 4);
    let r = test.run(
        |rng| Some(uniform_sphere([rng.next_f64(), rng.next_f64()])),
        |_| 1.0 / (4.0 * PI),
        0.0,
    );
    r.assert_passes(alpha(), 1e-9, "");
}

#[test]
fn cosine_hemisphere_passes() {
    // pdf zero on the lower hemisphere: those bins expect nothing.
    let test = SphereTest::new([20, 40], 400_000, 5);
    let r = test.run(
        |rng| {
            // Malley: uniform disk point lifted to the hemisphere.
            let r = rng.next_f64().sqrt();
            let phi = 2.0 * PI * rng.next_f64();
            let (x, y) = (r * phi.cos(), r * phi.sin());
            Some(DVec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt()))
        },
        |d| d.z.max(0.0) / PI,
        0.0,
    );
    r.assert_passes(alpha(), 1e-6, "");
}

#[test]
fn tilted_sphere_pdf_fails() {
    let test = SphereTest::new([20, 40], 400_000, 6);
    let r = test.run(
        |rng| Some(uniform_sphere([rng.next_f64(), rng.next_f64()])),
        |d| (1.0 + 0.05 * d.z) / (4.0 * PI),
        0.0,
    );
    println!("{r}");
    assert!((r.total_probability - 1.0).abs() < 1e-9);
    assert!(r.p_value < 1e-6, "{r}");
}

#[test]
fn sample_where_pdf_is_zero_fails() {
    // Uniform sphere judged against the upper-hemisphere pdf: samples in
    // bins of zero probability are impossible and fail outright.
    let test = SphereTest::new([10, 20], 10_000, 7);
    let r = test.run(
        |rng| Some(uniform_sphere([rng.next_f64(), rng.next_f64()])),
        |d| if d.z > 0.0 { 1.0 / (2.0 * PI) } else { 0.0 },
        0.0,
    );
    assert!(r.impossible_samples > 0 && r.p_value == 0.0, "{r}");
    assert!(r.to_string().contains("inf"), "{r}");
}

#[test]
fn out_of_domain_sample_fails() {
    let test = IntervalTest {
        a: 0.0,
        b: 1.0,
        bins: 10,
        samples: 1_000,
        seed: 8,
    };
    let r = test.run(|rng| Some(1.5 * rng.next_f64()), |_| 1.0, 0.0);
    assert!(r.invalid_samples > 0 && !r.passes(SIGNIFICANCE), "{r}");
}

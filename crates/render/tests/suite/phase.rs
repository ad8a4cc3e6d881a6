//! Henyey–Greenstein: normalisation, the forward-scattering convention,
//! agreement of `sample` with `pdf` (chi-square), and robustness at |g| → 1.

use fogbank_math::chi2::{adaptive_simpson, sidak, SphereTest, SIGNIFICANCE};
use fogbank_math::Pcg32;
use fogbank_render::world::phase::HenyeyGreenstein;
use glam::Vec3;
use std::f64::consts::PI;

/// The chi-square tests below share one 1 % false-alarm budget.
const CHI2_GS: [f32; 4] = [-0.7, 0.0, 0.3, 0.9];

/// An arbitrary, non-axis-aligned outgoing direction, so that the frame
/// construction around −wo is exercised.
fn wo() -> Vec3 {
    Vec3::new(0.3, -0.5, 0.8).normalize()
}

fn chi2(g: f32) {
    let hg = HenyeyGreenstein { g };
    let wo = wo();
    let test = SphereTest::new([20, 40], 400_000, 17);
    let r = test.run(
        |rng| {
            let u = [rng.next_f32(), rng.next_f32()];
            Some(hg.sample(wo, u).0.as_dvec3())
        },
        |d| hg.pdf(wo, d.as_vec3()) as f64,
        0.0,
    );
    r.assert_passes(
        sidak(SIGNIFICANCE, CHI2_GS.len() as u32),
        1e-4,
        &format!("g = {g}: "),
    );
}

#[test]
fn chi2_hg_backward_0_7() {
    chi2(CHI2_GS[0]);
}

#[test]
fn chi2_hg_isotropic() {
    chi2(CHI2_GS[1]);
}

#[test]
fn chi2_hg_forward_0_3() {
    chi2(CHI2_GS[2]);
}

#[test]
fn chi2_hg_forward_0_9() {
    chi2(CHI2_GS[3]);
}

/// Geometrically growing pieces of [0, end] so that adaptive Simpson
/// resolves lobes down to 10⁻⁶ wide.
fn integrate_geometric(f: impl Fn(f64) -> f64, end: f64) -> f64 {
    let mut edges = vec![0.0];
    let mut e = 1e-10;
    while e < end {
        edges.push(e);
        e *= 4.0;
    }
    edges.push(end);
    edges
        .windows(2)
        .map(|w| adaptive_simpson(&mut |x| f(x), w[0], w[1], 1e-10))
        .sum()
}

/// ∫ eval dω = 2π ∫₋₁¹ eval(cos θ) d cos θ, integrated in a = 1 ∓ cos θ
/// from the side of the lobe.
fn eval_sphere_integral(hg: HenyeyGreenstein) -> f64 {
    let sign = if hg.g >= 0.0 { 1.0 } else { -1.0 };
    2.0 * PI * integrate_geometric(|a| hg.eval((sign * (1.0 - a)) as f32) as f64, 2.0)
}

/// ∫ pdf(wo, ·) dω = 2π ∫₀^π pdf(wo, wi(t)) sin t dt with t the angle from
/// the lobe's peak. Unlike `eval`, whose f32 cos θ argument is quantised in
/// steps of 6·10⁻⁸ (the whole lobe of g = 0.999 spans about ten of them),
/// `pdf` sees directions and resolves even that lobe.
fn pdf_sphere_integral(hg: HenyeyGreenstein) -> f64 {
    let wo = Vec3::NEG_Z;
    let sign = if hg.g >= 0.0 { 1.0 } else { -1.0 };
    let f = |t: f64| {
        let wi = Vec3::new(t.sin() as f32, 0.0, (sign * t.cos()) as f32);
        hg.pdf(wo, wi) as f64 * t.sin()
    };
    2.0 * PI * integrate_geometric(f, PI)
}

#[test]
fn eval_integrates_to_one_over_the_sphere() {
    for g in [-0.9f32, -0.7, -0.3, 0.0, 1e-4, 0.3, 0.7, 0.9] {
        let integral = eval_sphere_integral(HenyeyGreenstein { g });
        assert!(
            (integral - 1.0).abs() < 1e-5,
            "g = {g}: ∫ eval dω = {integral}"
        );
    }
}

#[test]
fn pdf_integrates_to_one_over_the_sphere_up_to_g_0_999() {
    for g in [-0.999f32, -0.99, -0.7, 0.0, 0.3, 0.9, 0.99, 0.999] {
        let integral = pdf_sphere_integral(HenyeyGreenstein { g });
        assert!(
            (integral - 1.0).abs() < 1e-5,
            "g = {g}: ∫ pdf dω = {integral}"
        );
    }
}

#[test]
fn isotropic_and_peak_values_match_closed_forms() {
    let iso = HenyeyGreenstein::ISOTROPIC;
    for c in [-1.0, -0.3, 0.0, 0.5, 1.0] {
        assert!((iso.eval(c) as f64 - 1.0 / (4.0 * PI)).abs() < 1e-8);
    }
    // eval(±1) = (1 ± g) / (4π (1 ∓ g)²) in the forward / backward direction.
    for g in [-0.999f32, -0.5, 0.2, 0.999] {
        let hg = HenyeyGreenstein { g };
        let g = g as f64;
        let forward = (1.0 + g) / (4.0 * PI * (1.0 - g) * (1.0 - g));
        let backward = (1.0 - g) / (4.0 * PI * (1.0 + g) * (1.0 + g));
        assert!(
            (hg.eval(1.0) as f64 / forward - 1.0).abs() < 1e-5,
            "g = {g}"
        );
        assert!(
            (hg.eval(-1.0) as f64 / backward - 1.0).abs() < 1e-5,
            "g = {g}"
        );
    }
}

/// g > 0 is forward scattering: the mean cosine between the direction of
/// travel before (−wo) and after (wi) the collision is g.
#[test]
fn mean_cosine_is_g_and_positive_g_scatters_forward() {
    let wo = wo();
    let mut rng = Pcg32::new(3, 4);
    for g in [-0.999f32, -0.7, 0.0, 0.3, 0.9, 0.999] {
        let hg = HenyeyGreenstein { g };
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let (wi, _) = hg.sample(wo, [rng.next_f32(), rng.next_f32()]);
            sum += wi.dot(-wo) as f64;
        }
        let mean = sum / n as f64;
        // Var(cos θ) ≤ 1, so 5σ of the mean is at most 0.011.
        assert!((mean - g as f64).abs() < 0.011, "g = {g}: ⟨cos θ⟩ = {mean}");
    }
    // The most likely direction for g = 0.9 is straight on, along −wo.
    let hg = HenyeyGreenstein { g: 0.9 };
    assert!(hg.pdf(wo, -wo) > 100.0 * hg.pdf(wo, wo));
}

#[test]
fn sample_pdf_matches_pdf_and_eval_and_is_finite() {
    let wo = wo();
    let mut rng = Pcg32::new(5, 6);
    for g in [-0.999f32, -0.9, -0.3, -1e-6, 0.0, 1e-6, 0.3, 0.9, 0.999] {
        let hg = HenyeyGreenstein { g };
        // f32 direction rounding moves the pdf of a 10⁻³-rad-wide lobe by
        // up to a few 10⁻⁴ relative.
        let tolerance = if g.abs() > 0.99 { 3e-3 } else { 2e-5 };
        for i in 0..20_000 {
            let mut u = [rng.next_f32(), rng.next_f32()];
            // The ends of the unit square: ξ = 0 is the lobe's peak.
            if i == 0 {
                u = [0.0, 0.0];
            } else if i == 1 {
                u = [1.0 - f32::EPSILON / 2.0, 0.999_999_9];
            }
            let (wi, pdf) = hg.sample(wo, u);
            assert!(
                wi.is_finite() && pdf.is_finite() && pdf > 0.0,
                "g = {g}, u = {u:?}"
            );
            assert!((wi.length() - 1.0).abs() < 1e-5, "g = {g}, u = {u:?}");
            let p = hg.pdf(wo, wi);
            assert!(
                (p / pdf - 1.0).abs() < tolerance,
                "g = {g}, u = {u:?}: sample pdf {pdf}, pdf {p}"
            );
            let e = hg.eval(wi.dot(-wo));
            assert!(
                (e / p - 1.0).abs() < tolerance.max(1e-4) || g.abs() > 0.99,
                "g = {g}: eval {e}, pdf {p}"
            );
            // Reciprocity: the value depends only on the scattering angle.
            assert!((hg.pdf(-wi, -wo) / p - 1.0).abs() < 1e-5);
        }
    }
}

//! BSDFs: each sampler against its own pdf (chi-square over the sphere,
//! with the probability of no sample checked too), reciprocity, energy
//! bounds and the agreement of sample weights with `eval` (a white-furnace
//! style check: the directional albedo estimated from `sample` equals the
//! one estimated by integrating `eval` over uniform directions).

use fogbank_math::chi2::{sidak, SphereTest, SIGNIFICANCE};
use fogbank_math::Pcg32;
use fogbank_render::world::bsdf::{diffuse_fresnel, Bsdf, Microfacet, Plastic, RoughPlastic};
use glam::Vec3;

/// The chi-square tests below share one 1 % false-alarm budget.
const CHI2_TESTS: u32 = 41;

fn dir(theta_deg: f32, phi_deg: f32, below: bool) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    let z = if below { -t.cos() } else { t.cos() };
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), z)
}

fn chi2(name: &str, bsdf: Bsdf, wo: Vec3) {
    let sampler = |rng: &mut Pcg32| {
        let (uc, u) = (rng.next_f32(), [rng.next_f32(), rng.next_f32()]);
        // Delta lobes have no density: they count as "no sample".
        bsdf.sample(wo, uc, u)
            .filter(|s| !s.delta)
            .map(|s| s.wi.normalize().as_dvec3())
    };
    let pdf = |d: glam::DVec3| bsdf.pdf(wo, d.as_vec3()) as f64;
    let test = |samples| SphereTest::new([24, 48], samples, 29);
    // ∫ pdf < 1 where samples are lost (below the horizon, total internal
    // reflection of a sampled microfacet): that deficit is the probability
    // of no sample.
    let integral = test(1).run(sampler, pdf, 0.0).total_probability;
    let r = test(500_000).run(sampler, pdf, (1.0 - integral).max(0.0));
    println!("{name}: ∫pdf = {integral:.5}; {r}");
    assert!(integral <= 1.0 + 1e-3, "{name}: ∫pdf = {integral}");
    assert!(r.passes(sidak(SIGNIFICANCE, CHI2_TESTS)), "{name}: {r}");
}

#[test]
fn chi2_diffuse() {
    chi2(
        "diffuse",
        Bsdf::Diffuse {
            reflectance: Vec3::splat(0.5),
        },
        dir(40.0, 30.0, false),
    );
}

fn plastic(nonlinear: bool) -> Bsdf {
    Bsdf::Plastic(Plastic {
        diffuse: Vec3::new(0.2, 0.5, 0.8),
        specular: Vec3::ONE,
        eta: 1.49 / 1.000277,
        nonlinear,
    })
}

#[test]
fn chi2_plastic() {
    for (theta, nonlinear) in [(20.0, false), (75.0, true)] {
        chi2(
            &format!("plastic θo {theta}"),
            plastic(nonlinear),
            dir(theta, 30.0, false),
        );
    }
}

/// Beckmann with visible normals, or either distribution with normals
/// drawn from D cos θm.
fn beckmann(alpha: f32) -> Microfacet {
    Microfacet::beckmann(alpha)
}
fn all_normals(m: Microfacet) -> Microfacet {
    Microfacet {
        sample_visible: false,
        ..m
    }
}

/// The microfacet normal samplers against their densities: GGX and
/// Beckmann, visible from wo and from D cos θm, at three incidences.
#[test]
fn chi2_microfacet_normals() {
    for m in [
        Microfacet::ggx(0.3),
        beckmann(0.3),
        all_normals(Microfacet::ggx(0.3)),
        all_normals(beckmann(0.3)),
    ] {
        for theta in [10.0, 55.0, 85.0] {
            let wo = dir(theta, 40.0, false);
            let sampler =
                |rng: &mut Pcg32| Some(m.sample(wo, [rng.next_f32(), rng.next_f32()]).as_dvec3());
            let pdf = |d: glam::DVec3| m.pdf(wo, d.as_vec3()) as f64;
            let r =
                fogbank_math::chi2::SphereTest::new([24, 48], 500_000, 31).run(sampler, pdf, 0.0);
            println!("{m:?} θo {theta}: {r}");
            assert!(
                r.passes(sidak(SIGNIFICANCE, CHI2_TESTS)),
                "{m:?} θo {theta}: {r}"
            );
        }
    }
}

#[test]
fn chi2_rough_plastic() {
    for (mf, theta, nonlinear) in [
        (Microfacet::ggx(0.1), 20.0, false),
        (Microfacet::ggx(0.4), 50.0, true),
        (Microfacet::ggx(0.25), 80.0, false),
        (beckmann(0.3), 40.0, false),
        (all_normals(beckmann(0.2)), 70.0, true),
    ] {
        chi2(
            &format!("roughplastic {mf:?} θo {theta}"),
            Bsdf::RoughPlastic(RoughPlastic::new(
                Vec3::new(0.2, 0.5, 0.8),
                Vec3::ONE,
                1.5,
                mf,
                nonlinear,
            )),
            dir(theta, 30.0, false),
        );
    }
}

fn rough_conductor(mf: Microfacet) -> Bsdf {
    Bsdf::Conductor {
        eta: Vec3::new(0.2, 0.9, 1.1),
        k: Vec3::new(3.9, 2.4, 2.2),
        mf,
        specular: Vec3::ONE,
    }
}

#[test]
fn chi2_rough_conductor() {
    for (alpha, theta) in [(0.1, 15.0), (0.1, 70.0), (0.5, 15.0), (0.5, 70.0)] {
        for mf in [Microfacet::ggx(alpha), beckmann(alpha)] {
            chi2(
                &format!("roughconductor {mf:?} θo {theta}"),
                rough_conductor(mf),
                dir(theta, 60.0, false),
            );
        }
    }
    for mf in [
        all_normals(Microfacet::ggx(0.3)),
        all_normals(beckmann(0.3)),
    ] {
        chi2(
            &format!("roughconductor {mf:?} θo 40"),
            rough_conductor(mf),
            dir(40.0, 60.0, false),
        );
    }
}

#[test]
fn chi2_rough_dielectric() {
    for (alpha, theta, below) in [
        (0.2, 30.0, false),
        (0.6, 30.0, false),
        (0.2, 20.0, true),
        (0.6, 20.0, true),
        (0.3, 60.0, true),
        (0.3, 80.0, false),
    ] {
        chi2(
            &format!("roughdielectric α {alpha} θo {theta} below {below}"),
            Bsdf::Dielectric {
                eta: 1.5,
                mf: Microfacet::ggx(alpha),
            },
            dir(theta, 200.0, below),
        );
    }
    for (mf, theta, below) in [
        (beckmann(0.2), 30.0, false),
        (beckmann(0.6), 20.0, true),
        (beckmann(0.3), 80.0, false),
        (all_normals(beckmann(0.3)), 45.0, true),
    ] {
        chi2(
            &format!("roughdielectric {mf:?} θo {theta} below {below}"),
            Bsdf::Dielectric { eta: 1.5, mf },
            dir(theta, 200.0, below),
        );
    }
}

/// f(wo, wi)/η(wo)² = f(wi, wo)/η(wi)², η the IOR on each direction's
/// side (Veach 1997, §5.2; reflection: plain symmetry).
#[test]
fn reciprocity() {
    let mut rng = Pcg32::new(3, 4);
    let eta = 1.5f32;
    let bsdfs = [
        Bsdf::Diffuse {
            reflectance: Vec3::splat(0.7),
        },
        rough_conductor(Microfacet::ggx(0.3)),
        rough_conductor(beckmann(0.3)),
        Bsdf::Dielectric {
            eta,
            mf: Microfacet::ggx(0.3),
        },
        Bsdf::Dielectric {
            eta,
            mf: beckmann(0.3),
        },
        Bsdf::RoughPlastic(RoughPlastic::new(
            Vec3::splat(0.5),
            Vec3::ONE,
            1.5,
            Microfacet::ggx(0.3),
            false,
        )),
    ];
    let ior = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta };
    for b in bsdfs {
        for _ in 0..2000 {
            let mut d = || {
                Vec3::new(
                    2.0 * rng.next_f32() - 1.0,
                    2.0 * rng.next_f32() - 1.0,
                    2.0 * rng.next_f32() - 1.0,
                )
                .normalize()
            };
            let (wo, wi) = (d(), d());
            let (a, c) = (
                b.eval(wo, wi) / ior(wo).powi(2),
                b.eval(wi, wo) / ior(wi).powi(2),
            );
            assert!(
                (a - c).abs().max_element() <= 1e-3 * a.max_element().max(1.0),
                "{b:?}: {a} vs {c} at wo {wo}, wi {wi}"
            );
        }
    }
}

/// Mean and standard error of `n` draws of `f`.
fn mean_se(n: usize, mut f: impl FnMut() -> f64) -> (f64, f64) {
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let x = f();
        s += x;
        s2 += x * x;
    }
    let m = s / n as f64;
    (m, ((s2 / n as f64 - m * m).max(0.0) / n as f64).sqrt())
}

/// The albedo ∫ f |cos θi| dwi from `sample`'s weights equals the one from
/// `eval` at uniform directions on the sphere (`scale` weighs each
/// direction, e.g. η′² on transmission for energy); returns it.
fn albedo(b: Bsdf, wo: Vec3, scale: impl Fn(Vec3) -> f32) -> f64 {
    let n = 400_000;
    let mut rng = Pcg32::new(8, 1);
    let mut delta_sum = 0.0f64;
    let (sampled, se1) = mean_se(n, || {
        let s = b.sample(wo, rng.next_f32(), [rng.next_f32(), rng.next_f32()]);
        // Delta lobes: no density for `eval` to match; added to the
        // albedo afterwards.
        match s {
            Some(s) if s.delta => {
                delta_sum += (s.weight().x * scale(s.wi)) as f64;
                0.0
            }
            Some(s) => (s.weight().x * scale(s.wi)) as f64,
            None => 0.0,
        }
    });
    let mut rng = Pcg32::new(9, 1);
    let (uniform, se2) = mean_se(n, || {
        let z = 2.0 * rng.next_f32() - 1.0;
        let phi = 2.0 * std::f32::consts::PI * rng.next_f32();
        let s = (1.0 - z * z).max(0.0).sqrt();
        let wi = Vec3::new(s * phi.cos(), s * phi.sin(), z);
        (b.eval(wo, wi).x * wi.z.abs() * scale(wi) * 4.0 * std::f32::consts::PI) as f64
    });
    let se = (se1 * se1 + se2 * se2).sqrt();
    assert!(
        (sampled - uniform).abs() < 5.0 * se,
        "{b:?} at {wo}: sampled {sampled} vs uniform {uniform} (se {se})"
    );
    sampled + delta_sum / n as f64
}

#[test]
fn sample_weights_agree_with_eval_and_energy_is_bounded() {
    // A white conductor (F ≈ 1): albedo ≤ 1, near 1 when smooth-ish.
    let white = |mf| Bsdf::Conductor {
        eta: Vec3::ONE,
        k: Vec3::splat(1e4),
        mf,
        specular: Vec3::ONE,
    };
    for mf in [Microfacet::ggx as fn(f32) -> Microfacet, beckmann] {
        let a = albedo(white(mf(0.05)), dir(30.0, 0.0, false), |_| 1.0);
        assert!(a > 0.97 && a < 1.0 + 1e-3, "{a}");
        let a = albedo(white(mf(0.8)), dir(60.0, 0.0, false), |_| 1.0);
        assert!(a < 1.0, "{a}");
        let a = albedo(white(all_normals(mf(0.5))), dir(70.0, 0.0, false), |_| 1.0);
        assert!(a < 1.0, "{a}");
    }
    // Diffuse: exactly the reflectance.
    let a = albedo(
        Bsdf::Diffuse {
            reflectance: Vec3::splat(0.6),
        },
        dir(10.0, 0.0, false),
        |_| 1.0,
    );
    assert!((a - 0.6).abs() < 2e-3, "{a}");
    // Plastic: the diffuse lobe's weights match eval, and its albedo is
    // ρ′ (1 − F(θo)) (1 − F_dr,ext) / η², ρ′ = ρ/(1 − F_dr,int) (linear) or
    // ρ/(1 − ρ F_dr,int) (nonlinear), plus F(θo) from the coating.
    let eta = 1.49f64 / 1.000277;
    let wo = dir(40.0, 0.0, false);
    let f_o = fogbank_render::world::bsdf::fresnel::dielectric(wo.z, eta as f32) as f64;
    let fdr_int = diffuse_fresnel(1.0 / eta as f32) as f64;
    let fdr_ext = diffuse_fresnel(eta as f32) as f64;
    for nonlinear in [false, true] {
        let rho = 0.2;
        let base = if nonlinear {
            rho / (1.0 - rho * fdr_int)
        } else {
            rho / (1.0 - fdr_int)
        };
        let want = base * (1.0 - f_o) * (1.0 - fdr_ext) / (eta * eta) + f_o;
        let a = albedo(plastic(nonlinear), wo, |_| 1.0);
        assert!(
            (a - want).abs() < 0.01,
            "plastic (nonlinear {nonlinear}): {a} vs {want}"
        );
    }
    // Rough dielectric: reflection + η′²·transmission ≤ 1 from both sides
    // (undoing the radiance scaling gives the energy).
    let eta = 1.5f32;
    for (theta, below) in [(30.0, false), (20.0, true), (70.0, false)] {
        let wo = dir(theta, 10.0, below);
        let energy = |wi: Vec3| {
            if wi.z * wo.z > 0.0 {
                1.0
            } else if wo.z > 0.0 {
                eta * eta
            } else {
                1.0 / (eta * eta)
            }
        };
        for mf in [
            Microfacet::ggx(0.1),
            beckmann(0.1),
            all_normals(beckmann(0.1)),
        ] {
            let a = albedo(Bsdf::Dielectric { eta, mf }, wo, energy);
            assert!(a > 0.95 && a < 1.0 + 2e-3, "θ {theta}, below {below}: {a}");
        }
    }
}

/// Smooth lobes: the Fresnel split and the exact directions.
#[test]
fn smooth_dielectric_and_conductor_and_thin_and_null() {
    let eta = 1.5f32;
    let b = Bsdf::Dielectric {
        eta,
        mf: Microfacet::ggx(0.0),
    };
    let wo = dir(45.0, 0.0, false);
    let r = fogbank_render::world::bsdf::fresnel::dielectric(wo.z, eta);
    let mut rng = Pcg32::new(1, 1);
    let n = 200_000;
    let mut reflected = 0;
    for _ in 0..n {
        let s = b.sample(wo, rng.next_f32(), [0.5, 0.5]).unwrap();
        assert!(s.delta);
        if s.wi.z > 0.0 {
            reflected += 1;
            assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
            assert!((s.weight().x - 1.0).abs() < 1e-5);
        } else {
            // Snell, and the radiance weight 1/η².
            assert!((s.wi.x.abs() * eta - wo.x.abs()).abs() < 1e-5);
            assert!((s.weight().x - 1.0 / (eta * eta)).abs() < 1e-5);
        }
    }
    let p = reflected as f64 / n as f64;
    let se = (r as f64 * (1.0 - r as f64) / n as f64).sqrt();
    assert!((p - r as f64).abs() < 5.0 * se, "{p} vs {r}");
    // Inside beyond the critical angle: always reflected.
    let inside = dir(60.0, 0.0, true);
    assert!(b.sample(inside, 0.999, [0.5, 0.5]).unwrap().wi.z < 0.0);
    // Conductor mirror: weight = Fresnel.
    let c = rough_conductor(Microfacet::ggx(0.0))
        .sample(wo, 0.5, [0.5, 0.5])
        .unwrap();
    assert!(c.delta && (c.wi.z - wo.z).abs() < 1e-6);
    // Thin dielectric: straight through or mirrored, weight 1.
    let t = Bsdf::ThinDielectric { eta };
    for uc in [0.01, 0.99] {
        let s = t.sample(wo, uc, [0.5, 0.5]).unwrap();
        assert!(
            (s.wi + wo).length() < 1e-6 || (s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6
        );
        assert!((s.weight().x - 1.0).abs() < 1e-5);
    }
    // Null: straight through, weight 1.
    let s = Bsdf::Null.sample(wo, 0.5, [0.5, 0.5]).unwrap();
    assert!((s.wi + wo).length() < 1e-6 && (s.weight().x - 1.0).abs() < 1e-6);
}

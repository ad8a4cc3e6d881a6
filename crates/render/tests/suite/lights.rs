//! Light sampling for next-event estimation: delta lights, selection by
//! power, and the light BVH against selection by power in a render.

use fogbank_math::Vec3;
use fogbank_render::lights::sample::{spot_falloff, LightSampler, LightSelection, Vertex};
use fogbank_render::lights::{Light, SpotCurve};

#[test]
fn spot_light_is_full_inside_zero_outside_and_smooth_between() {
    let (start, total) = (25f32.to_radians().cos(), 30f32.to_radians().cos());
    assert_eq!(spot_falloff(1.0, start, total, SpotCurve::Smoothstep), 1.0);
    assert_eq!(
        spot_falloff(
            31f32.to_radians().cos(),
            start,
            total,
            SpotCurve::Smoothstep
        ),
        0.0
    );
    let mut last = 0.0;
    for deg in (0..=10).map(|i| 30.0 - i as f32 * 0.5) {
        let k = spot_falloff(deg.to_radians().cos(), start, total, SpotCurve::Smoothstep);
        assert!(k >= last && (0.0..=1.0).contains(&k), "{deg}°: {k}");
        last = k;
    }
    let spot = Light::Spot {
        position: Vec3::new(0.0, 2.0, 0.0),
        direction: Vec3::new(0.0, -1.0, 0.0),
        intensity: Vec3::splat(8.0),
        cos_falloff_start: start,
        cos_total: total,
        curve: SpotCurve::Smoothstep,
    };
    let below = spot.sample_li(Vec3::ZERO, [0.5, 0.5]).unwrap();
    assert!(
        below.is_delta && (below.radiance - Vec3::splat(2.0)).length() < 1e-6,
        "{below:?}"
    );
    assert!((below.wi - Vec3::Y).length() < 1e-6 && (below.distance - 2.0).abs() < 1e-6);
    assert!(spot
        .sample_li(Vec3::new(5.0, 0.0, 0.0), [0.5, 0.5])
        .is_none());
}

#[test]
fn light_selection_follows_power_and_sums_to_one() {
    let lights = vec![
        Light::Point {
            position: Vec3::ZERO,
            intensity: Vec3::splat(1.0),
        },
        Light::Point {
            position: Vec3::X,
            intensity: Vec3::splat(3.0),
        },
        Light::Constant {
            radiance: Vec3::ZERO,
        },
    ];
    let s = LightSampler::new(&lights, 1.0, LightSelection::Auto);
    for at in [Vertex::Medium, Vertex::Surface] {
        let pmf = |i| s.pmf(i, at, Vec3::ZERO);
        assert!((pmf(0) - 0.25).abs() < 1e-6 && (pmf(1) - 0.75).abs() < 1e-6 && pmf(2) == 0.0);
        let mut counts = [0usize; 3];
        let n = 100_000;
        for i in 0..n {
            let (k, p) = s.pick((i as f32 + 0.5) / n as f32, at, Vec3::ZERO).unwrap();
            assert_eq!(p, pmf(k));
            counts[k] += 1;
        }
        assert_eq!(counts[2], 0);
        assert!((counts[1] as f64 / n as f64 - 0.75).abs() < 1e-3);
        assert!(LightSampler::new(&[], 1.0, LightSelection::Auto)
            .pick(0.5, at, Vec3::ZERO)
            .is_none());
    }
}

/// A surface sees one hemisphere of an environment: its weight there is
/// a quarter of its power (4π·πR²·L), the directional light's unchanged.
#[test]
fn surfaces_weigh_environments_by_the_hemisphere_they_see() {
    let lights = vec![
        Light::Constant {
            radiance: Vec3::splat(1.0 / (4.0 * std::f32::consts::PI)),
        },
        Light::Directional {
            direction: -Vec3::Y,
            irradiance: Vec3::splat(1.0),
        },
    ];
    let s = LightSampler::new(&lights, 2.0, LightSelection::Auto);
    assert!((s.pmf(0, Vertex::Medium, Vec3::ZERO) - 0.5).abs() < 1e-6);
    assert!((s.pmf(0, Vertex::Surface, Vec3::ZERO) - 0.2).abs() < 1e-6);
    assert!((s.pmf(1, Vertex::Surface, Vec3::ZERO) - 0.8).abs() < 1e-6);
}

/// Mitsuba 3's spot profile: linear in the angle between the beam width and
/// the cutoff (20° and 15° here: half way at 17.5°), 1 inside, 0 outside.
#[test]
fn linear_spot_curve_is_linear_in_the_angle() {
    let cos = |deg: f32| deg.to_radians().cos();
    let k = |deg: f32| spot_falloff(cos(deg), cos(15.0), cos(20.0), SpotCurve::Linear);
    assert_eq!(k(10.0), 1.0);
    assert_eq!(k(20.5), 0.0);
    for (deg, want) in [(17.5, 0.5), (16.0, 0.8), (19.0, 0.2)] {
        assert!((k(deg) - want).abs() < 1e-3, "{deg}°: {} vs {want}", k(deg));
    }
}

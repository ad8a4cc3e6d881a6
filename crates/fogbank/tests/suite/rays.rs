//! Estimators on the caller's rays against the transmittance integrator:
//! on the camera's pixel-centre rays they are the 1-spp render, bit for
//! bit, for every estimator; the result does not depend on threads.

use fogbank::rays::{
    camera_rays, sample_distance_on_rays, transmittance_on_rays, FlightSampler, Rays,
};
use fogbank::{load_scene, Progress, RenderJob, Renderer};
use fogbank_estimators::estimator::TrackLength;
use fogbank_estimators::Estimator;

fn scene(estimator: &str) -> fogbank::Scene {
    let o = [
        "integrator.type=transmittance".to_string(),
        format!("integrator.estimator={estimator}"),
        "render.pixel_jitter=false".into(),
        "render.seed=5".into(),
        "camera.width=12".into(),
        "camera.height=9".into(),
        "media.0.density.resolution=24".into(),
    ];
    let path = fogbank_math::sample_data::repo_root().join("scenes/transmittance.toml");
    load_scene(Some(&path), &o).unwrap()
}

#[test]
fn estimates_on_camera_rays_are_the_transmittance_render() {
    let renderer = Renderer::cpu(2).unwrap();
    for e in Estimator::all() {
        let s = scene(e.name());
        let job = RenderJob {
            spp: Some(3),
            ..Default::default()
        };
        let film = job
            .run(&renderer, &s, &Progress::default(), None)
            .unwrap()
            .film;
        let (o, d, t) = camera_rays(&s);
        let rays = Rays {
            origins: &o,
            directions: &d,
            t_max: &t,
        };
        let (est, lookups) = transmittance_on_rays(
            &renderer,
            &s.media[0].medium,
            e,
            rays,
            3,
            5,
            &Progress::default(),
        )
        .unwrap();
        for (i, px) in film.sums.iter().enumerate() {
            // The film sums the f32 radiance (background 1) exactly.
            let mut sum = fogbank_math::ExactSum::default();
            est[i * 3..i * 3 + 3].iter().for_each(|&v| sum.add_f64(v));
            assert_eq!(
                px.sum[0].to_le_bytes(),
                sum.to_le_bytes(),
                "{}: pixel {i}",
                e.name()
            );
        }
        assert_eq!(
            film.lookups,
            lookups.iter().map(|&n| n as u64).sum::<u64>(),
            "{}",
            e.name()
        );
    }
}

#[test]
fn estimates_do_not_depend_on_threads_or_direction_length() {
    let s = scene("jackknife");
    let (o, d, t) = camera_rays(&s);
    let run = |threads, d: &[[f32; 3]], t: &[f32]| {
        let rays = Rays {
            origins: &o,
            directions: d,
            t_max: t,
        };
        transmittance_on_rays(
            &Renderer::cpu(threads).unwrap(),
            &s.media[0].medium,
            Estimator::parse("ratio_tracking").unwrap(),
            rays,
            4,
            9,
            &Progress::default(),
        )
        .unwrap()
    };
    let a = run(1, &d, &t);
    assert_eq!(a, run(2, &d, &t));
    // Directions twice as long with half the t_max: the same segments.
    let d2: Vec<[f32; 3]> = d.iter().map(|v| v.map(|x| 2.0 * x)).collect();
    let t2: Vec<f32> = t.iter().map(|x| x / 2.0).collect();
    let b = run(2, &d2, &t2);
    let close =
        a.0.iter()
            .zip(&b.0)
            .filter(|(x, y)| (*x - *y).abs() > 1e-5)
            .count();
    assert!(
        close * 50 < a.0.len(),
        "{close} of {} estimates moved",
        a.0.len()
    );
}

#[test]
fn bad_rays_and_samplers_are_refused_naming_the_ray() {
    let s = scene("ratio_tracking");
    let r = Renderer::cpu(1).unwrap();
    let m = &s.media[0].medium;
    let o = [[0.0f32; 3]; 2];
    let err = |d: &[[f32; 3]], t: &[f32]| {
        transmittance_on_rays(
            &r,
            m,
            Estimator::TrackLength(TrackLength),
            Rays {
                origins: &o,
                directions: d,
                t_max: t,
            },
            1,
            0,
            &Progress::default(),
        )
        .unwrap_err()
        .to_string()
    };
    assert!(err(&[[0.0, 0.0, 1.0], [0.0; 3]], &[1.0, 1.0]).contains("ray 1: direction is zero"));
    assert!(err(&[[0.0, 0.0, 1.0]; 2], &[1.0, f32::NAN]).contains("ray 1: t_max"));
    assert!(err(&[[0.0, 0.0, 1.0]], &[1.0, 1.0]).contains("one entry per ray"));
    assert!(FlightSampler::parse("equiangular", None)
        .unwrap_err()
        .to_string()
        .contains("light="));
    assert!(FlightSampler::parse("delta", None)
        .unwrap_err()
        .to_string()
        .contains("unknown sampler `delta`"));
    let ok = sample_distance_on_rays(
        &r,
        m,
        FlightSampler::parse("delta_tracking", None).unwrap(),
        Rays {
            origins: &o,
            directions: &[[0.0, 0.0, 1.0]; 2],
            t_max: &[f32::INFINITY; 2],
        },
        2,
        0,
        &Progress::default(),
    )
    .unwrap();
    assert_eq!(ok.t.len(), 4);
}

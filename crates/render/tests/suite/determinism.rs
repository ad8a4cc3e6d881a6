//! A render is a function of scene, seed and sample index: bit-identical
//! images for any thread count.

use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::Path;

const SCENE: &str = include_str!("../scenes/two_media.toml");

fn film_with_threads(scene: &Scene, threads: usize, seed: u32) -> fogbank_render::Film {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let opts = RenderOptions::new(3, seed);
    pool.install(|| render(scene, &opts, &Progress::default()))
        .film
}

#[test]
fn same_seed_same_image_for_one_and_two_threads() {
    for estimator in ["ratio_tracking", "track_length", "analytic_trilinear"] {
        let desc = parse_scene(
            SCENE,
            "test",
            &[format!("integrator.estimator={estimator}")],
        )
        .unwrap();
        let scene = Scene::build(desc, Path::new(".")).unwrap();
        let a = film_with_threads(&scene, 1, 5);
        let b = film_with_threads(&scene, 2, 5);
        assert_eq!(
            a.sums, b.sums,
            "{estimator}: sums differ between 1 and 2 threads"
        );
        assert_eq!(a.count, b.count);
        assert_eq!(a.lookups, b.lookups);
        if estimator != "analytic_trilinear" {
            let c = film_with_threads(&scene, 2, 6);
            assert_ne!(
                a.sums, c.sums,
                "{estimator}: a different seed must change the image"
            );
        }
    }
}

/// `render` groups short passes into batches (each row takes several sample
/// indices before the threads join); `render_observed` renders pass by
/// pass. The films are the same bit for bit.
#[test]
fn batched_passes_equal_pass_by_pass() {
    let desc = parse_scene(SCENE, "test", &["integrator.type=volpath".to_string()]).unwrap();
    let scene = Scene::build(desc, Path::new(".")).unwrap();
    let opts = RenderOptions::new(37, 4);
    let batched = render(&scene, &opts, &Progress::default()).film;
    let mut passes = 0;
    let single =
        fogbank_render::render_observed(&scene, &opts, &Progress::default(), &mut |_, _| {
            passes += 1
        })
        .film;
    assert_eq!(passes, 37);
    assert!(batched.sums == single.sums);
    assert_eq!(batched.count, single.count);
    assert_eq!(batched.lookups, single.lookups);
    assert!(batched.count.iter().all(|&c| c == 37));
}

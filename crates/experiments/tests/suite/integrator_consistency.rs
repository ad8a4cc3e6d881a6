//! Unbiased configurations of the scattering integrators agree per pixel
//! under the z-test (seed-fixed, so deterministic), and the test has the
//! power to reject a configuration that is known to differ.

use fogbank_eval::image_io::Image;
use fogbank_eval::metrics::ztest::ztest;
use fogbank_experiments::harness::protocol::render_at;
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

/// A nearest-filtered cloud (so regular tracking is exact) under a dim
/// environment, with a point light inside and a sun.
const SCENE: &str = "[camera]\nwidth = 12\nheight = 10\nfov = 45.0\n\
    [[media]]\ndensity = { procedural = \"cloud\", resolution = 24, seed = 3 }\n\
    sigma_t_scale = 10.0\nalbedo = [0.9, 0.8, 0.7]\nphase = { type = \"hg\", g = 0.5 }\nfilter = \"nearest\"\n\
    [[lights]]\ntype = \"constant\"\nradiance = [0.3, 0.4, 0.5]\n\
    [[lights]]\ntype = \"point\"\nposition = [0.05, 0.1, 0.0]\nintensity = [0.3, 0.3, 0.2]\n\
    [[lights]]\ntype = \"directional\"\ndirection = [-0.3, -1.0, -0.2]\nirradiance = [1.5, 1.4, 1.2]\n\
    [integrator]\ntype = \"volpath\"\nmax_depth = 16\n";

fn image(extra: &[&str], spp: u32, seed: u32) -> Image {
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let scene = Scene::build(parse_scene(SCENE, "test", &extra).unwrap(), Path::new(".")).unwrap();
    let film = render_at(&scene, spp, seed).film;
    assert_eq!(film.nan_samples + film.inf_samples, 0, "{extra:?}");
    film.mean_image()
}

fn configs(integrator: &str) -> Vec<Vec<String>> {
    [
        ("delta_tracking", "track_length"),
        ("decomposition_tracking", "ratio_tracking"),
        ("regular_tracking", "residual_ratio_tracking"),
        ("delta_tracking", "unbiased_ray_marching"),
    ]
    .iter()
    .map(|(s, e)| {
        vec![
            format!("integrator.type={integrator}"),
            format!("integrator.distance_sampler={s}"),
            format!("integrator.estimator={e}"),
        ]
    })
    .collect()
}

/// Every configuration of `integrator` against its default (delta tracking
/// + ratio-tracking NEE) rendered with 4× the samples.
fn check_all_agree(integrator: &str, spp: u32) {
    let it = format!("integrator.type={integrator}");
    let reference = image(&[&it], 4 * spp, 100);
    for (i, c) in configs(integrator).iter().enumerate() {
        let args: Vec<&str> = c.iter().map(String::as_str).collect();
        let test = image(&args, spp, 200 + i as u32);
        let z = ztest(&reference, &test).unwrap();
        assert!(
            z.pass,
            "{c:?} vs default {integrator}: {} failing pixels, max |z| {:.2} > {:.2} at {:?}",
            z.failing_pixels, z.max_abs_z, z.threshold, z.max_abs_z_pixel
        );
    }
}

#[test]
fn volpath_configurations_agree() {
    check_all_agree("volpath", 256);
    // The baseline preset (decomposition + residual ratio tracking).
    let reference = image(&[], 512, 7);
    let baseline = image(&["integrator.preset=baseline"], 256, 8);
    assert!(ztest(&reference, &baseline).unwrap().pass);
    // Lin et al. 2021's baseline exactly: light sampling only, roulette by albedo.
    let paper = image(&["integrator.preset=restir_baseline"], 256, 9);
    let z = ztest(&reference, &paper).unwrap();
    assert!(
        z.pass,
        "restir_baseline: max |z| {:.2} at {:?}",
        z.max_abs_z, z.max_abs_z_pixel
    );
}

#[test]
fn direct_configurations_agree() {
    check_all_agree("direct", 256);
}

/// Power: single scattering is visibly less than 16 bounces, and a
/// one-sample ray-marching NEE is visibly biased, at these sample counts.
#[test]
fn the_z_test_rejects_different_images() {
    let reference = image(&[], 512, 7);
    let direct = image(&["integrator.type=direct"], 256, 9);
    assert!(!ztest(&reference, &direct).unwrap().pass);
    let biased = image(
        &["integrator.estimator=ray_marching", "integrator.samples=1"],
        256,
        10,
    );
    let z = ztest(&reference, &biased).unwrap();
    assert!(
        !z.pass,
        "ray marching with one sample passed: max |z| {}",
        z.max_abs_z
    );
}

//! Post-interpolative transfer functions on the GPU:
//! extinction classified after interpolation, colour → albedo and emission
//! at the interpolated scalar, for every place the CPU classifies (filtered
//! lookups, regular tracking's voxels) — per-pixel z-test against the CPU
//! on lavapipe.

use fogbank_gpu::test_gpu;
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

use crate::support;
use support::assert_gpu_matches_cpu;

fn scene(extra: &[&str]) -> Scene {
    let text = "[camera]\nwidth = 20\nheight = 16\nfov = 30.0\n\
         [[media]]\ndensity = { procedural = \"cloud\", resolution = 32, seed = 5 }\nsigma_t_scale = 30.0\n\
         precision = \"f32\"\n\
         transfer = { opacity = [[0.0, 0.0], [0.2, 0.0], [0.25, 1.0], [0.3, 0.1], [1.0, 0.6]], \
         color = [[0.0, 1.0, 0.3, 0.2], [0.5, 0.4, 0.9, 0.6], [1.0, 0.9, 0.9, 1.0]], \
         emission = [[0.2, 0.0, 0.0, 0.0], [0.6, 2.0, 0.8, 0.1]] }\n\
         [[lights]]\ntype = \"constant\"\nradiance = [0.3, 0.4, 0.5]\n\
         [[lights]]\ntype = \"point\"\nposition = [0.6, 0.7, 0.5]\nintensity = [1.5, 1.4, 1.2]\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 6\n";
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    Scene::build(parse_scene(text, "test", &extra).unwrap(), Path::new(".")).unwrap()
}

#[test]
fn classified_media_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    for extra in [
        vec![],
        vec!["integrator.estimator=\"track_length\""],
        vec![
            "media.0.filter=\"nearest\"",
            "integrator.distance_sampler=\"regular_tracking\"",
            "integrator.estimator=\"regular_tracking\"",
        ],
        vec![
            "integrator.type=\"transmittance\"",
            "integrator.estimator=\"ratio_tracking\"",
        ],
    ] {
        let s = scene(&extra);
        assert!(s.world.media[0].medium.opacity.is_some());
        assert_gpu_matches_cpu(&gpu, &s, 128, 0.01, &format!("{extra:?}"));
    }
}

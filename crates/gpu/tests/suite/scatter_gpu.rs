//! GPU `direct` and `volpath` against the CPU reference: per-pixel z-test
//! at equal spp and matching lookup counts, for every distance sampler,
//! several NEE estimators and every light type (lavapipe in CI).

use fogbank_gpu::{render as gpu_render, test_gpu};
use fogbank_render::{parse_scene, Progress, RenderOptions, Scene};
use std::path::Path;

use crate::support;
use support::assert_gpu_matches_cpu;

pub fn scene(lights: &str, extra: &[String]) -> Scene {
    let text = format!(
        "[camera]\nwidth = 20\nheight = 16\nfov = 30.0\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 32, seed = 5 }}\nsigma_t_scale = 12.0\n\
         albedo = [0.9, 0.8, 0.7]\nphase = {{ type = \"hg\", g = 0.4 }}\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 16, seed = 9 }}\nsigma_t_scale = 5.0\n\
         albedo = [0.6, 0.7, 0.9]\nphase = {{ type = \"hg\", g = -0.3 }}\n\
         to_world = {{ translate = [0.2, 0.1, 0.1], scale = 0.6 }}\n\
         {lights}\n[integrator]\ntype = \"volpath\"\n"
    );
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    Scene::build(parse_scene(&text, "test", extra).unwrap(), &base).unwrap()
}

const MIXED: &str = "[[lights]]\ntype = \"constant\"\nradiance = [0.3, 0.4, 0.5]\n\
    [[lights]]\ntype = \"point\"\nposition = [0.05, 0.1, 0.0]\nintensity = [0.3, 0.3, 0.2]\n\
    [[lights]]\ntype = \"directional\"\ndirection = [-0.3, -1.0, -0.2]\nirradiance = [1.5, 1.4, 1.2]\n\
    [[lights]]\ntype = \"spot\"\nposition = [0.0, 0.9, 0.3]\ndirection = [0.0, -1.0, -0.2]\nintensity = [2.0, 2.0, 2.0]\n";
/// Mitsuba 3's spot profile (linear in the angle), its transition band
/// across the cloud.
const LINEAR_SPOT: &str = "[[lights]]\ntype = \"spot\"\nposition = [0.1, 0.2, 1.5]\n\
    direction = [0.0, 0.0, -1.0]\nintensity = [6.0, 8.0, 10.0]\n\
    cone_angle = 30.0\nfalloff_start = 5.0\ncurve = \"linear\"\n";
const PROBE: &str =
    "[[lights]]\ntype = \"envmap\"\nfile = \"probes/sky.hdr\"\nrotate = [0.0, 1.0, 0.0, 40.0]\n";

fn compare(lights: &str, extra: &[&str], spp: u32) {
    let Some(gpu) = test_gpu() else { return };
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    assert_gpu_matches_cpu(
        &gpu,
        &scene(lights, &extra),
        spp,
        0.01,
        &format!("{extra:?}"),
    );
}

#[test]
fn direct_matches_the_cpu_for_every_sampler_and_light() {
    for (sampler, nee) in [
        ("delta_tracking", "ratio_tracking"),
        ("decomposition_tracking", "track_length"),
        ("regular_tracking", "jackknife"),
    ] {
        let args = [
            "integrator.type=direct".to_string(),
            format!("integrator.distance_sampler={sampler}"),
            format!("integrator.estimator={nee}"),
            "media.0.filter=nearest".into(),
            "media.1.filter=nearest".into(),
        ];
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        compare(MIXED, &args, 256);
    }
    compare(
        PROBE,
        &["integrator.type=direct", "integrator.estimator=jackknife"],
        256,
    );
    compare(LINEAR_SPOT, &["integrator.type=direct"], 256);
}

#[test]
fn volpath_matches_the_cpu() {
    compare(MIXED, &["integrator.max_depth=8"], 256);
    compare(
        PROBE,
        &[
            "integrator.preset=baseline",
            "integrator.max_depth=12",
            "media.0.filter=trilinear",
        ],
        256,
    );
    // Lin et al. 2021's baseline: light sampling only, roulette by albedo.
    compare(
        PROBE,
        &[
            "integrator.preset=restir_baseline",
            "integrator.max_depth=5",
            "media.0.supervoxel=8",
        ],
        256,
    );
    compare(
        MIXED,
        &[
            "integrator.preset=restir_baseline",
            "integrator.max_depth=3",
        ],
        256,
    );
    // Instances of one medium (Hansen 2025 Fig. 4.10), uploaded once.
    compare(
        MIXED,
        &[
            "integrator.max_depth=4",
            "media.1.instances=[{ translate = [0.0, 0.0, 0.0] }, { translate = [-0.35, 0.05, 0.1], rotate = [0.0, 1.0, 0.0, 30.0] }]",
        ],
        128,
    );
}

#[test]
fn cpu_only_features_are_clear_errors() {
    let Some(gpu) = test_gpu() else { return };
    let s = scene(
        MIXED,
        // (Constant analytic grids upload as constant bricks; others do not.)
        &["media.0.albedo_grid={ procedural = \"ramp\", value = 0.2, gradient = [0.5, 0.0, 0.0] }"
            .to_string()],
    );
    let opts = RenderOptions::new(1, 0);
    let e = gpu_render::render(&gpu, &s, &opts, &Progress::default())
        .err()
        .unwrap();
    assert!(e.0.contains("analytic"), "{e}");
}

#[test]
fn point_mis_matches_the_cpu_for_every_strategy() {
    let Some(gpu) = test_gpu() else { return };
    let text = "[camera]\nwidth = 14\nheight = 12\nfov = 24.0\n\
        [[media]]\ndensity = { procedural = \"cloud\", resolution = 32, seed = 5 }\nsigma_t_scale = 12.0\n\
        albedo = [0.9, 0.8, 0.7]\nphase = { type = \"hg\", g = 0.4 }\nfilter = \"nearest\"\n\
        [[lights]]\ntype = \"point\"\nposition = [0.05, 0.1, 0.0]\nintensity = [0.3, 0.3, 0.2]\n\
        [[lights]]\ntype = \"point\"\nposition = [-0.15, -0.05, 0.1]\nintensity = [0.2, 0.25, 0.3]\n\
        [integrator]\ntype = \"point_mis\"\nestimator = \"jackknife\"\n";
    for (strategy, filter) in [
        ("free_flight", "nearest"),
        ("equiangular", "nearest"),
        ("mis_miller", "nearest"),
        ("mis_naive", "nearest"),
        ("mis_jackknife", "nearest"),
        ("mis_jackknife_biased", "nearest"),
        ("mis_jackknife_biased", "stochastic_trilinear"),
    ] {
        let extra = vec![
            format!("integrator.strategy={strategy}"),
            format!("media.0.filter={filter}"),
        ];
        let s = Scene::build(parse_scene(text, "t", &extra).unwrap(), Path::new(".")).unwrap();
        assert_gpu_matches_cpu(&gpu, &s, 192, 1e-3, &format!("{strategy}/{filter}"));
    }
    // Shapes as opaque occluders (occluders.wgsl): one hides part of the
    // view, one shadows part of the cloud.
    let occluded = format!(
        "{text}[[shapes]]\ntype = \"rectangle\"\nto_world = {{ translate = [-0.15, 0.0, 0.75], scale = 0.1 }}\n\
         bsdf = {{ type = \"diffuse\", reflectance = 0.0 }}\n\
         [[shapes]]\ntype = \"rectangle\"\n\
         to_world = {{ translate = [0.15, 0.0, 0.0], rotate = [0.0, 1.0, 0.0, 90.0], scale = 0.3 }}\n\
         bsdf = {{ type = \"diffuse\", reflectance = 0.0 }}\n"
    );
    for strategy in ["mis_jackknife", "equiangular"] {
        let extra = vec![format!("integrator.strategy={strategy}")];
        let s = Scene::build(parse_scene(&occluded, "t", &extra).unwrap(), Path::new(".")).unwrap();
        assert_gpu_matches_cpu(&gpu, &s, 192, 1e-3, &format!("{strategy} with occluders"));
    }
}

/// Albedo grids (scalar and RGB) and emission (colour × grid, blackbody of
/// a temperature grid) on the GPU against the CPU.
#[test]
fn medium_properties_match_the_cpu() {
    let dir = std::env::temp_dir().join(format!("fogbank_gpu_props_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A 3-channel RGB albedo grid and a scalar grid, as Mitsuba .vol files.
    let n = 6u32;
    let mut rgb = Vec::new();
    let mut scalar = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let (x, y, z) = (i as f32 / 5.0, j as f32 / 5.0, k as f32 / 5.0);
                rgb.extend([0.3 + 0.6 * x, 0.9 - 0.5 * y, 0.5 + 0.4 * z]);
                scalar.push(3000.0 + 4000.0 * x * y + 1000.0 * z);
            }
        }
    }
    let bbox = [-0.5, -0.5, -0.5, 0.5, 0.5, 0.5];
    fogbank_volume::loaders::vol::write_vol(&dir.join("albedo.vol"), [n; 3], 3, bbox, &rgb)
        .unwrap();
    fogbank_volume::loaders::vol::write_vol(&dir.join("temp.vol"), [n; 3], 1, bbox, &scalar)
        .unwrap();
    let albedo = format!(
        "media.0.albedo_grid={{ vol = \"{}\" }}",
        dir.join("albedo.vol").display()
    );
    let temp = format!(
        "media.0.emission={{ temperature = {{ vol = \"{}\" }}, scale = 0.5 }}",
        dir.join("temp.vol").display()
    );
    let glow = format!(
        "media.0.emission={{ color = [1.0, 0.5, 0.2], grid = {{ vol = \"{}\", channel = 1 }} }}",
        dir.join("albedo.vol").display()
    );
    compare(MIXED, &[&albedo, "integrator.max_depth=6"], 256);
    compare(
        MIXED,
        &[
            &temp,
            "media.0.albedo=[0.5, 0.5, 0.5]",
            "integrator.type=direct",
        ],
        256,
    );
    compare(PROBE, &[&glow, &albedo, "integrator.max_depth=4"], 256);
    let _ = std::fs::remove_dir_all(&dir);
}

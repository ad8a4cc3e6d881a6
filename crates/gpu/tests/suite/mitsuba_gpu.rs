//! Mitsuba 3 XML scenes on the GPU: the wgpu backend
//! renders `scenes/mitsuba/*.xml` as they are. In CI (lavapipe) four scenes
//! are z-tested against the CPU at equal samples (the CPU itself is held to
//! the Mitsuba references in crates/scene/tests/suite/mitsuba.rs); the
//! ignored tests — the light BVH and jackknife NEE in chromatic media, each
//! a pipeline of its own, and the GPU held to the same Mitsuba 3 `scalar_rgb`
//! references by the same criterion as the CPU, at 2·10⁶–2·10⁷ samples per
//! image — minutes per scene on lavapipe, seconds on a real GPU:
//! `cargo test --release -p fogbank-gpu --test gpu mitsuba_gpu -- --ignored`.

use fogbank_gpu::{render as gpu_render, test_gpu};
use fogbank_render::{parse_scene, Progress, RenderOptions, Scene};
use fogbank_scene::load_scene;

use crate::support;
use support::assert_gpu_matches_cpu;

use crate::support::mitsuba_agreement;
use mitsuba_agreement::{assert_agrees, reference_scenes, scenes, spp_for};

fn scene(name: &str) -> Scene {
    load_scene(Some(&scenes().join(format!("{name}.xml"))), &[]).unwrap()
}

/// GPU against CPU at `spp`.
fn matches_cpu(name: &str, spp: u32) {
    let Some(gpu) = test_gpu() else { return };
    assert_gpu_matches_cpu(&gpu, &scene(name), spp, 1e-4, name);
}

/// GPU against the Mitsuba reference, as the CPU is.
fn agrees_with_mitsuba(name: &str) {
    let Some(gpu) = test_gpu() else { return };
    let opts = RenderOptions::new(spp_for(name), 11);
    let r = gpu_render::render(&gpu, &scene(name), &opts, &Progress::default()).unwrap();
    assert_agrees(name, &r.film);
}

// Two tests of two scenes each (lavapipe creates each volpath pipeline in
// half a minute or more, so CI covers the features with four scenes: null
// boundaries, nested media and meshes; thin dielectric and area light;
// smooth and rough dielectrics around homogeneous media; plastics,
// textures, twosided and a bilinear envmap; bitmaps with every filter and
// wrap mode). Mitsuba's spot light is covered by scatter_gpu_test (a
// `linear` spot). The ignored test below covers all eleven scenes
// against Mitsuba.
#[test]
fn null_boundaries_and_thin_dielectrics_match_the_cpu() {
    matches_cpu("null_mesh_medium", 48);
    matches_cpu("thin_area", 48);
}

#[test]
fn dielectrics_and_textured_plastics_match_the_cpu() {
    matches_cpu("dielectric_media", 48);
    matches_cpu("surfaces_env_area", 48);
    matches_cpu("bitmap_textures", 48);
}

/// Shape groups placed by instances: the two-level walk (bvh.wgsl: the
/// top level's leaves are instances, each group walked in its own space)
/// and hits placed back in the world, as on the CPU.
#[test]
fn instanced_shape_groups_match_the_cpu() {
    matches_cpu("instances", 48);
}

/// Analytic spheres and disks (analytic_shapes.wgsl) and their lights
/// (shape_lights.wgsl: cone-sampled sphere, elliptical disk).
/// And a furnace: a sphere emitting inward around the camera (sampled by
/// area from inside).
#[test]
fn analytic_spheres_and_disks_match_the_cpu() {
    matches_cpu("analytic_shapes", 48);
    let Some(gpu) = test_gpu() else { return };
    let furnace = "[camera]\nfrom = [0.1, -0.5, 0.2]\nto = [0, 1, 0]\nwidth = 8\nheight = 8\n\
                   [[shapes]]\ntype = \"sphere\"\nflip_normals = true\n\
                   bsdf = { type = \"diffuse\", reflectance = 0.5 }\nemitter = { radiance = [1, 1, 1] }\n\
                   [integrator]\ntype = \"volpath\"\nmax_depth = 3\n";
    let s = Scene::build(
        parse_scene(furnace, "furnace", &[]).unwrap(),
        std::path::Path::new("."),
    )
    .unwrap();
    assert_gpu_matches_cpu(&gpu, &s, 64, 1e-4, "inward emitting sphere");
}

/// 300 small emitting triangles in fog picked through the light BVH
/// (`render.light_sampler = "bvh"`; light_bvh.wgsl) on both devices; MIS
/// weights of emission hit by phase-sampled directions re-derive its pmf.
/// A pipeline of its own (LIGHT_BVH), so a device test: lavapipe's cold
/// compile costs CI two minutes; CI checks the GPU's BVH picks against the
/// CPU's (`diagnostics::light_picks` in suite/bvh_gpu.rs).
#[test]
#[ignore = "its own pipeline: minutes of cold compilation on lavapipe; run with --ignored on a GPU"]
fn many_emitters_through_the_light_bvh_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let path = scenes().join("fog_emitters.xml");
    let s = load_scene(Some(&path), &["render.light_sampler=bvh".into()]).unwrap();
    let fogbank_render::integrators::IntegratorKind::VolPath(v) = &s.integrator else {
        panic!("fog_emitters renders with volpath");
    };
    assert!(
        v.lights.bvh().is_some(),
        "the emitters are picked through the BVH"
    );
    assert_gpu_matches_cpu(&gpu, &s, 64, 1e-4, "fog_emitters with a light BVH");
}

/// Chromatic extinction, homogeneous and gridded (constant k), NEE by
/// ratio tracking and by the jackknife: both devices estimate every
/// channel's transmittance from one walk (`fogbank_estimators::scaled`,
/// frame.wgsl `estimate_rgb`), so images and lookups agree.
#[test]
fn chromatic_media_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    assert_gpu_matches_cpu(&gpu, &scene("chromatic"), 128, 1e-4, "chromatic");
}

/// [`chromatic_media_match_the_cpu`] with jackknife NEE: a pipeline of its
/// own (ESTIMATOR), so a device test like the light BVH's.
#[test]
#[ignore = "its own pipeline: minutes of cold compilation on lavapipe; run with --ignored on a GPU"]
fn chromatic_media_with_jackknife_nee_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let path = scenes().join("chromatic.xml");
    let jackknife = load_scene(Some(&path), &["integrator.estimator=jackknife".into()]).unwrap();
    assert_gpu_matches_cpu(&gpu, &jackknife, 96, 1e-4, "chromatic, jackknife NEE");
}

/// `transmittance` with surfaces (null cubes around a homogeneous and a
/// gridded medium) and chromatic media: the scatter kernel's shadow walk
/// along the camera ray, as the CPU's. (One scene: on lavapipe each
/// further pipeline costs CI about a minute of compilation.)
#[test]
fn transmittance_through_surfaces_and_chromatic_media_matches_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let overrides = ["integrator={type=\"transmittance\",background=[1.0,0.8,0.6]}".to_string()];
    let s = load_scene(Some(&scenes().join("chromatic.xml")), &overrides).unwrap();
    assert!(
        s.world.surfaces.is_some(),
        "chromatic.xml bounds its media by null cubes"
    );
    assert_gpu_matches_cpu(&gpu, &s, 512, 1e-3, "chromatic");
}

/// Scenes written as Mitsuba's users write them (users_*.xml): Beckmann
/// microfacets at Mitsuba's defaults and sampling normals from D cos θ
/// (microfacet.wgsl), a camera in fog with near and far clip planes
/// (frame.wgsl's camera_ray and camera_ray_end; the path lost at the far
/// plane inside a medium), spectra converted when read.
#[test]
fn beckmann_clip_planes_and_spectra_match_the_cpu() {
    matches_cpu("users_beckmann_conductor", 48);
    matches_cpu("users_beckmann_dielectric", 48);
    matches_cpu("users_beckmann_plastic", 48);
    matches_cpu("users_clip_fog", 48);
}

#[test]
#[ignore = "minutes per scene on lavapipe; run with --ignored on a GPU"]
fn every_surface_scene_agrees_with_mitsuba_on_the_gpu() {
    // FOGBANK_MITSUBA_SCENES=a,b narrows the list (one pipeline each).
    let only = std::env::var("FOGBANK_MITSUBA_SCENES").unwrap_or_default();
    for name in reference_scenes() {
        if !only.is_empty() && !only.split(',').any(|n| n == name) {
            continue;
        }
        agrees_with_mitsuba(&name);
        eprintln!("{name}: agrees with Mitsuba");
    }
}

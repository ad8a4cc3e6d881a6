//! Instanced media (Hansen 2025 Fig. 4.10): one `[[media]]` entry placed many
//! times shares its grid; it renders exactly like separate entries at the
//! same placements (every instance sampled separately, the nearest
//! collision wins, transmittances multiply); pins share one grid across
//! rigid copies; bad placements are refused naming the key.

use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::Path;
use std::sync::Arc;

const HEAD: &str =
    "[camera]\nfrom = [0.0, 0.0, 3.0]\nto = [0.0, 0.0, 0.0]\nfov = 50.0\nwidth = 16\nheight = 12\n\
    [[lights]]\ntype = \"constant\"\nradiance = [0.5, 0.6, 0.8]\n\
    [[lights]]\ntype = \"point\"\nposition = [0.0, 1.0, 1.0]\nintensity = [1.0, 1.0, 1.0]\n\
    [integrator]\ntype = \"volpath\"\nmax_depth = 6\n";

const CLOUD: &str = "density = { procedural = \"cloud\", resolution = 24, seed = 3 }\n\
    sigma_t_scale = 15.0\nalbedo = [0.9, 0.9, 0.9]\nto_world = { translate = [-0.5, -0.5, -0.5] }\n";

const PLACES: [&str; 3] = [
    "{ translate = [-0.6, 0.0, 0.0] }",
    "{ translate = [0.4, 0.1, -0.3], rotate = [0.0, 1.0, 0.0, 35.0] }",
    "{ translate = [0.0, -0.2, 0.4], rotate = [1.0, 0.0, 0.0, 20.0] }",
];

fn scene(text: &str, extra: &[&str]) -> Result<Scene, String> {
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let desc = parse_scene(text, "test", &extra).map_err(|e| e.to_string())?;
    Scene::build(desc, Path::new(".")).map_err(|e| e.to_string())
}

fn instanced() -> String {
    format!(
        "{HEAD}[[media]]\n{CLOUD}instances = [{}]\n",
        PLACES.join(", ")
    )
}

/// The same placements written as separate entries.
fn separate() -> String {
    let mut s = HEAD.to_string();
    for p in PLACES {
        // `instances` applies after `to_world`: translate the centring first.
        let one = format!("[[media]]\n{CLOUD}instances = [{p}]\n");
        s += &one;
    }
    s
}

#[test]
fn instances_render_like_separate_media() {
    let opts = RenderOptions::new(8, 5);
    let a = render(
        &scene(&instanced(), &[]).unwrap(),
        &opts,
        &Progress::default(),
    )
    .film;
    let b = render(
        &scene(&separate(), &[]).unwrap(),
        &opts,
        &Progress::default(),
    )
    .film;
    assert_eq!(a.mean(), b.mean());
    let s = scene(&instanced(), &[]).unwrap();
    assert_eq!(s.world.media.len(), 3);
    assert!(a.mean().iter().any(|p| p[0] > 0.0));
}

#[test]
fn pins_share_one_grid_across_rigid_instances() {
    let s = scene(
        &instanced(),
        &["integrator.pins=ms", "integrator.pin_grid.positions=3"],
    )
    .unwrap();
    let IntegratorKind::VolPath(v) = &s.integrator else {
        panic!()
    };
    let grids = &v.pin_set(&s.world).unwrap().media;
    let g0 = grids[0].as_ref().unwrap();
    assert!(grids.iter().all(|g| Arc::ptr_eq(g.as_ref().unwrap(), g0)));
    // A scaled copy has other optical depths: its own grid.
    let scaled = format!(
        "{HEAD}[[media]]\n{CLOUD}instances = [{}, {{ scale = 0.5 }}]\n",
        PLACES[0]
    );
    let s = scene(
        &scaled,
        &["integrator.pins=ms", "integrator.pin_grid.positions=3"],
    )
    .unwrap();
    let IntegratorKind::VolPath(v) = &s.integrator else {
        panic!()
    };
    let grids = &v.pin_set(&s.world).unwrap().media;
    assert!(!Arc::ptr_eq(
        grids[0].as_ref().unwrap(),
        grids[1].as_ref().unwrap()
    ));
}

#[test]
fn bad_instances_are_refused_by_key() {
    let singular = format!(
        "{HEAD}[[media]]\n{CLOUD}instances = [{}, {{ scale = 0.0 }}]\n",
        PLACES[0]
    );
    let e = scene(&singular, &[]).err().unwrap();
    assert!(
        e.contains("media.0.instances.1") && e.contains("singular"),
        "{e}"
    );
    let emissive = format!(
        "{HEAD}[[media]]\n{CLOUD}emission = {{ scale = 2.0 }}\ninstances = [{}]\n",
        PLACES[0]
    );
    let e = scene(&emissive, &[]).err().unwrap_or_default();
    assert!(
        e.contains("media.0.instances") && e.contains("cannot be instanced"),
        "{e}"
    );
}

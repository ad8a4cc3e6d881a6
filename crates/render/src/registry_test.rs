//! Adding an integrator is its own file and one line of the `integrators!`
//! list: `test_background` (compiled only for tests) appears in the
//! registry every scene is read through (and, being test-only, not in the
//! list `fogbank integrators` prints), its keys are validated by
//! `--set`, and its table round-trips through a scene file and renders.

use crate::integrators::{IntegratorDesc, IntegratorKind, LISTED, REGISTRY};
use crate::params::markdown_table;
use crate::scene::{parse_scene, Scene, DEFAULT_SCENE};
use crate::{render, Progress, RenderOptions};
use std::path::Path;

fn with(overrides: &[&str]) -> Result<crate::SceneDesc, String> {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    parse_scene(DEFAULT_SCENE, "built-in", &o).map_err(|e| e.0)
}

#[test]
fn a_registered_integrator_is_listed_with_its_table() {
    let (_, params) = REGISTRY
        .iter()
        .find(|(n, _)| *n == "test_background")
        .expect("registered in one line");
    let unlisted: Vec<&str> = (REGISTRY.iter())
        .filter(|(n, _)| LISTED.iter().all(|(l, _)| l != n))
        .map(|(n, _)| *n)
        .collect();
    assert!(unlisted.contains(&"test_background"), "{unlisted:?}");
    assert!(
        unlisted.iter().all(|n| n.starts_with("test_")),
        "{unlisted:?}"
    );
    assert!(markdown_table(params).contains("| `level` | 0.5 |"));
    // Its module doc carries the same table, as every integrator's does.
    let doc = include_str!("integrators/test_background.rs");
    assert!(doc.contains(
        &markdown_table(params)
            .replace('\n', "\n//! ")
            .trim_end_matches("//! ")
            .to_string()
    ));
}

#[test]
fn set_validates_its_keys_and_the_scene_round_trips() {
    let desc = with(&["integrator.type=test_background", "integrator.level=2.0"]).unwrap();
    assert_eq!(desc.integrator.name(), "test_background");
    let text = toml::to_string(&desc).unwrap();
    assert!(
        text.contains("type = \"test_background\"") && text.contains("level = 2.0"),
        "{text}"
    );
    assert_eq!(parse_scene(&text, "round trip", &[]).unwrap(), desc);
    let e = with(&["integrator.type=test_background", "integrator.levle=1"]).unwrap_err();
    assert!(
        e.contains("integrator.levle") && e.contains("test_background") && e.contains("level"),
        "{e}"
    );
    let e = with(&["integrator.type=test_background", "integrator.level=-1"]).unwrap_err();
    assert!(e.contains("integrator.level"), "{e}");
    // Switching a file's integrator away with --set drops its keys, as for
    // every integrator.
    let back = parse_scene(&text, "file", &["integrator.type=volpath".into()]).unwrap();
    assert_eq!(back.integrator.name(), "volpath");
}

#[test]
fn it_builds_and_renders_what_its_line_says() {
    let desc = with(&[
        "integrator.type=test_background",
        "integrator.level=0.25",
        "camera.width=8",
        "camera.height=6",
        "media.0.density.resolution=16",
    ])
    .unwrap();
    let scene = Scene::build(desc, Path::new(".")).unwrap();
    assert!(matches!(
        scene.integrator,
        IntegratorKind::TestBackground(_)
    ));
    let opts = RenderOptions::new(1, 1);
    let r = render(&scene, &opts, &Progress::default());
    let mean = r.film.mean();
    assert!(mean
        .iter()
        .all(|p| p.iter().all(|&c| (0.0..=0.25 + 1e-6).contains(&c))));
    assert!(
        mean.iter().any(|p| (p[0] - 0.25).abs() < 1e-6),
        "some pixels miss the medium"
    );
    let _ = IntegratorDesc::default();
}

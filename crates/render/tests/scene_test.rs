//! Scene files: the built-in scene, round-tripping, and errors that name the
//! key at fault.

use fogbank_render::{parse_scene, Scene, SceneDesc, DEFAULT_SCENE};
use std::path::Path;

#[test]
fn default_scene_builds_and_round_trips() {
    let desc = SceneDesc::default_scene();
    let text = toml::to_string(&desc).unwrap();
    let again = parse_scene(&text, "round trip", &[]).unwrap();
    assert_eq!(desc, again);
    let small = parse_scene(
        DEFAULT_SCENE,
        "built-in",
        &["media.0.density.resolution=24".into()],
    )
    .unwrap();
    Scene::build(small, Path::new(".")).unwrap();
}

#[test]
fn overrides_set_nested_keys_and_array_entries() {
    let d = parse_scene(
        DEFAULT_SCENE,
        "built-in",
        &[
            "integrator.estimator=track_length".into(),
            "media.0.sigma_t_scale=40".into(),
            "camera.from=[1, 2, 3]".into(),
        ],
    )
    .unwrap();
    assert_eq!(d.integrator.estimator, "track_length");
    assert_eq!(d.media[0].sigma_t_scale, 40.0);
    assert_eq!(d.camera.from, [1.0, 2.0, 3.0]);
}

fn err(overrides: &[&str]) -> String {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match parse_scene(DEFAULT_SCENE, "built-in", &o) {
        Ok(d) => match Scene::build(d, Path::new(".")) {
            Ok(_) => panic!("{overrides:?} should fail"),
            Err(e) => e.to_string(),
        },
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_keys_and_values_are_named() {
    let e = err(&["integrator.estimatorr=x"]);
    assert!(e.contains("estimatorr"), "{e}");
    let e = err(&["media.0.sigma_t_scale=abc"]);
    assert!(e.contains("sigma_t_scale"), "{e}");
    let e = err(&["media.3.sigma_t_scale=1"]);
    assert!(e.contains("media.3") && e.contains("out of range"), "{e}");
    let e = err(&["integrator.estimator=nonsense"]);
    assert!(
        e.contains("integrator.estimator") && e.contains("nonsense"),
        "{e}"
    );
    let e = err(&["media.0.filter=cubic"]);
    assert!(e.contains("media.0.filter"), "{e}");
    let e = err(&["camera.width=0"]);
    assert!(e.contains("camera"), "{e}");
    let e = err(&["media.0.density.vdb=missing.vdb"]);
    assert!(e.contains("media.0.density"), "{e}");
    let e = err(&["novalue"]);
    assert!(e.contains("KEY=VALUE"), "{e}");
}

#[test]
fn missing_files_name_the_file() {
    let d = parse_scene(
        "[[media]]\ndensity = { vol = \"nope.vol\" }\n",
        "inline",
        &[],
    )
    .unwrap();
    let e = Scene::build(d, Path::new("/tmp")).unwrap_err().to_string();
    assert!(e.contains("nope.vol"), "{e}");
}

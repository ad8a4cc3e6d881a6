//! Scene files: the built-in scene, round-tripping, and errors that name the
//! key at fault.

use fogbank_render::{
    parse_scene, Scene, SceneDesc, DEFAULT_SCENE, TRANSMITTANCE_SCENE as TRANSMITTANCE,
};
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
    let scene = Scene::build(small, Path::new(".")).unwrap();
    // The first impression: a lit cloud, multiple scattering under a sky
    // and the sun, tone-mapped for display.
    assert_eq!(scene.integrator.name(), "volpath");
    let kinds: Vec<&str> = scene.lights.iter().map(|l| l.kind()).collect();
    assert_eq!(kinds, ["envmap", "directional"]);
    assert_eq!(desc.render.tonemap, fogbank_image::ToneCurve::Agx);
    let t = parse_scene(TRANSMITTANCE, "scenes/transmittance.toml", &[]).unwrap();
    assert_eq!(t.integrator.name(), "transmittance");
}

#[test]
fn overrides_set_nested_keys_and_array_entries() {
    let d = parse_scene(
        TRANSMITTANCE,
        "built-in",
        &[
            "integrator.estimator=track_length".into(),
            "media.0.sigma_t_scale=40".into(),
            "camera.from=[1, 2, 3]".into(),
        ],
    )
    .unwrap();
    assert_eq!(d.integrator.estimator().name(), "track_length");
    assert_eq!(d.media[0].sigma_t_scale.max(), 40.0);
    assert_eq!(d.camera.from, [1.0, 2.0, 3.0]);
}

fn err(overrides: &[&str]) -> String {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match parse_scene(TRANSMITTANCE, "built-in", &o) {
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

/// A scene with `[integrator]` as given, parsed from the file's text.
fn file_err(integrator: &str) -> String {
    let text = format!("{TRANSMITTANCE}\n").replace(
        "[integrator]\ntype = \"transmittance\"\nestimator = \"ratio_tracking\"\n",
        &format!("[integrator]\n{integrator}\n"),
    );
    match parse_scene(&text, "scene.toml", &[]) {
        Ok(_) => panic!("{integrator:?} should fail"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn misplaced_and_misspelt_integrator_keys_are_refused() {
    // In the file: the message names the key, the integrator and its keys.
    let e = file_err("type = \"transmittance\"\nmax_depth = 4");
    assert!(
        e.contains(
            "integrator.max_depth is not a parameter of \"transmittance\" with estimator \"ratio_tracking\"; it takes estimator, background, roulette"
        ) && e.contains("line"),
        "{e}"
    );
    let e = file_err("type = \"volpath\"\nbackground = [0, 0, 0]");
    assert!(
        e.contains("integrator.background is not a parameter of \"volpath\"")
            && e.contains("it takes distance_sampler, estimator, preset, max_depth, rr_depth")
            && e.contains("is a parameter of transmittance"),
        "{e}"
    );
    let e = file_err("type = \"direct\"\nmax_depht = 4");
    assert!(
        e.contains("integrator.max_depht is not a parameter of \"direct\"")
            && e.contains("it takes distance_sampler, estimator, preset"),
        "{e}"
    );
    let e = file_err("type = \"point_mis\"\nrr_depth = 2");
    assert!(
        e.contains("integrator.rr_depth is not a parameter of \"point_mis\"")
            && e.contains("it takes strategy, estimator, mis_samples"),
        "{e}"
    );
    // Through --set.
    let e = err(&["integrator.max_depth=4"]);
    assert!(
        e.contains("integrator.max_depth is not a parameter of \"transmittance\""),
        "{e}"
    );
    let e = err(&["integrator.type=volpath", "integrator.strategy=equiangular"]);
    assert!(
        e.contains("integrator.strategy is not a parameter of \"volpath\"")
            && e.contains("is a parameter of point_mis"),
        "{e}"
    );
    let e = err(&["integrator.type=direct", "integrator.rr_depth=3"]);
    assert!(
        e.contains("integrator.rr_depth is not a parameter of \"direct\""),
        "{e}"
    );
    let e = err(&["integrator.type=point_mis", "integrator.preset=baseline"]);
    assert!(
        e.contains("integrator.preset is not a parameter of \"point_mis\""),
        "{e}"
    );
    // An estimator option the estimator does not take.
    let e = err(&["integrator.samples=4"]);
    assert!(
        e.contains("integrator.samples is not a parameter of \"transmittance\" with estimator \"ratio_tracking\"; it takes estimator, background, roulette"),
        "{e}"
    );
    let e = err(&["integrator.estimator=jackknife", "integrator.clip=true"]);
    assert!(
        e.contains("with estimator \"jackknife\"")
            && e.contains("estimator, background, samples, mode, step, jitter"),
        "{e}"
    );
    let e = err(&["integrator.estimator={ type = \"ray_marching\", mult = 2 }"]);
    assert!(
        e.contains("integrator.estimator.mult is not a parameter of \"ray_marching\"; it takes type, samples, clip"),
        "{e}"
    );
}

#[test]
fn estimators_take_their_options_flat_or_as_a_table() {
    let parse = |o: &[&str]| {
        let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
        parse_scene(TRANSMITTANCE, "built-in", &o).unwrap()
    };
    let flat = parse(&["integrator.estimator=jackknife", "integrator.samples=20"]);
    let table = parse(&["integrator.estimator={ type = \"jackknife\", samples = 20 }"]);
    assert_eq!(flat, table);
    assert_eq!(
        format!("{:?}", flat.integrator.estimator()),
        "Jackknife { samples: 20, mode: FixedCount, jitter: Stratified }"
    );
    // Every integrator round-trips through its table, options included.
    for o in [
        &["integrator.estimator={ type = \"ray_marching\", samples = 3, clip = true }"][..],
        &[
            "integrator.type=volpath",
            "integrator.preset=baseline",
            "integrator.max_depth=7",
        ],
        &[
            "integrator.type=direct",
            "integrator.distance_sampler=regular_tracking",
        ],
        &[
            "integrator.type=point_mis",
            "integrator.strategy=equiangular",
            "integrator.estimator=jackknife",
            "integrator.mode=fixed_step",
            "integrator.step=0.5",
        ],
    ] {
        let d = parse(o);
        let again = parse_scene(&toml::to_string(&d).unwrap(), "round trip", &[]).unwrap();
        assert_eq!(d, again, "{o:?}");
    }
}

#[test]
fn switching_the_integrator_with_set_drops_the_old_integrators_keys() {
    let volpath = TRANSMITTANCE.replace(
        "[integrator]\ntype = \"transmittance\"\nestimator = \"ratio_tracking\"\n",
        "[integrator]\ntype = \"volpath\"\nmax_depth = 5\nrr_depth = 2\nestimator = \"jackknife\"\nsamples = 4\n",
    );
    let o = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    // The file's volpath keys go; the estimator and its options stay.
    let d = parse_scene(&volpath, "scene", &o(&["integrator.type=direct"])).unwrap();
    assert_eq!(d.integrator.name(), "direct");
    assert_eq!(d.integrator.estimator().name(), "jackknife");
    let d = parse_scene(&volpath, "scene", &o(&["integrator.type=transmittance"])).unwrap();
    assert_eq!(d.integrator.name(), "transmittance");
    // A key given with --set is not dropped: misplaced, it is refused.
    let e = parse_scene(
        &volpath,
        "scene",
        &o(&["integrator.type=direct", "integrator.max_depth=3"]),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("integrator.max_depth is not a parameter of \"direct\""),
        "{e}"
    );
    // In the file itself a misplaced key is refused as before.
    let bad = volpath.replace("type = \"volpath\"", "type = \"direct\"");
    assert!(parse_scene(&bad, "scene", &[]).is_err());
}

#[test]
fn the_explosion_scene_glows_and_quantity_is_checked() {
    use fogbank_render::{render, Progress, RenderOptions};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/explosion.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mean = |extra: &[&str]| {
        let mut o: Vec<String> = [
            "camera.width=16",
            "camera.height=12",
            "media.0.density.resolution=32",
        ]
        .iter()
        .chain(extra)
        .map(|s| s.to_string())
        .collect();
        o.push("media.0.emission.temperature.resolution=32".into());
        let scene =
            Scene::build(parse_scene(&text, "explosion", &o).unwrap(), Path::new(".")).unwrap();
        let opts = RenderOptions::new(4, 1);
        let m = render(&scene, &opts, &Progress::default()).film.mean();
        m.iter().map(|p| p[0] as f64).sum::<f64>() / m.len() as f64
    };
    let (glow, dark) = (mean(&[]), mean(&["media.0.emission.scale=0"]));
    assert!(glow > 3.0 * dark, "emission {glow} vs none {dark}");
    let e = err(&["media.0.density={ procedural = \"cloud\", quantity = \"temperature\" }"]);
    assert!(e.contains("media.0.density.quantity"), "{e}");
    let e = err(&["media.0.density={ procedural = \"explosion\", quantity = \"heat\" }"]);
    assert!(
        e.contains("media.0.density.quantity") && e.contains("heat"),
        "{e}"
    );
}

/// The README's MRI scene parses (its data is fetched by tools/fetch_data.sh mni,
/// so CI only checks the keys, and that a missing file is named).
#[test]
fn mri_brain_scene_parses_and_names_missing_data() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mri_brain.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let desc = parse_scene(&text, "mri_brain.toml", &[]).unwrap();
    assert_eq!(desc.integrator.name(), "visopt");
    assert_eq!(desc.media[0].importance.len(), 1);
    let base = Path::new("/nonexistent");
    let e = Scene::build(desc, base)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(
        e.contains("media.0.density") && e.contains("mni_t1.nii.gz"),
        "{e}"
    );
}

/// Half floats end at 65504: a grid with larger values is refused under
/// the default `f16` storage, naming the medium's `precision`, instead of
/// being stored as infinities (an opaque box), and renders with `f32`.
#[test]
fn values_beyond_f16_are_refused_unless_stored_as_f32() {
    let dir = std::env::temp_dir().join(format!("fogbank-f16-range-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let values: Vec<u8> = (0..64)
        .flat_map(|i| if i % 2 == 0 { 9.0e4f32 } else { 1.0e5 }.to_le_bytes())
        .collect();
    std::fs::write(dir.join("dense.raw"), values).unwrap();
    let scene = |precision: &str| {
        let text = format!(
            "[[media]]\ndensity = {{ raw = \"dense.raw\", dims = [4, 4, 4], type = \"f32\" }}\n\
             sigma_t_scale = 1e-5\n{precision}"
        );
        Scene::build(parse_scene(&text, "f16 range", &[]).unwrap(), &dir)
    };
    let err = scene("").expect_err("f16 cannot hold 1e5").to_string();
    assert!(
        err.contains("media.0.density")
            && err.contains("65504")
            && err.contains("media.0.precision = \"f32\""),
        "{err}"
    );
    let m = scene("precision = \"f32\"\n").unwrap();
    assert_eq!(m.media[0].medium.data.value_range(), (9.0e4, 1.0e5));
    std::fs::remove_dir_all(&dir).ok();
}

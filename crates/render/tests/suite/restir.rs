//! The `restir` integrator's plumbing: its parameters and errors, the
//! camera projection temporal reuse relies on, and reproducibility. Its
//! unbiasedness against `volpath` is tested in
//! `crates/eval/tests/suite/restir_unbiased.rs`.

use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::Path;

const CLOUD: &str = include_str!("../scenes/restir_cloud.toml");

fn build(text: &str, set: &[&str]) -> Result<Scene, String> {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    parse_scene(text, "test", &set)
        .and_then(|d| Scene::build(d, Path::new(".")))
        .map_err(|e| e.0)
}

#[test]
fn camera_project_inverts_ray() {
    let s = build(CLOUD, &[]).unwrap();
    let cam = &s.camera;
    for (x, y) in [(0.5, 0.5), (10.25, 3.75), (19.5, 13.5)] {
        let r = cam.ray(x, y);
        let (px, py) = cam.project(r.at(1.7)).unwrap();
        assert!(
            (px - x).abs() < 1e-3 && (py - y).abs() < 1e-3,
            "{x},{y} → {px},{py}"
        );
    }
    assert!(cam.project(cam.origin - cam.ray(10.0, 7.0).d).is_none());
}

#[test]
fn restir_parameters_read_back_and_refuse_bad_values() {
    let s = build(
        CLOUD,
        &["integrator.max_depth=5", "integrator.mis=stochastic"],
    )
    .unwrap();
    let t = s.desc.integrator.to_table();
    assert_eq!(t["max_depth"].as_integer(), Some(5));
    assert_eq!(t["mis"].as_str(), Some("stochastic"));
    assert_eq!(t["estimator"].as_str(), Some("analytic_trilinear"));
    for (set, expect) in [
        (
            "integrator.max_depth=9",
            "integrator.max_depth: 9 is outside 1..=8",
        ),
        (
            "integrator.reuse=both",
            "is not none, spatial, temporal or spatiotemporal",
        ),
        (
            "integrator.mis=balance",
            "is not talbot, stochastic, uniform or pairwise",
        ),
        (
            "integrator.reuse_mip=4",
            "integrator.reuse_mip: 4 is outside 0..=3",
        ),
        ("integrator.estimator=track_length", ""),
        ("integrator.estimator=biased_ray_marching", "final shading"),
        ("integrator.rr_depth=0", "integrator.rr_depth"),
        ("integrator.shift=vertex", ""),
        ("integrator.shift=edge", "is not direction or vertex"),
    ] {
        let r = build(CLOUD, &[set]);
        if expect.is_empty() {
            assert!(r.is_ok(), "{set}: {r:?}");
        } else {
            let e = r.err().unwrap_or_else(|| panic!("{set} accepted"));
            assert!(e.contains(expect), "{set}: {e}");
        }
    }
}

#[test]
fn restir_refuses_scenes_it_cannot_render() {
    let two =
        format!("{CLOUD}\n[[media]]\ndensity = {{ procedural = \"cloud\", resolution = 8 }}\n");
    let e = build(&two, &[]).err().unwrap();
    assert!(e.contains("exactly one medium (this one has 2)"), "{e}");
    let analytic = CLOUD.replace(
        "{ procedural = \"cloud\", resolution = 24, seed = 3 }",
        "{ procedural = \"sphere\", resolution = 16 }",
    );
    let e = build(&analytic, &[]).err().unwrap();
    assert!(e.contains("needs a voxel grid"), "{e}");
    // Shapes of every kind, emitting or not, join paths; BSDFs
    // with a delta lobe cannot (light sampling alone ends the paths), nor
    // can the vertex shift keep a vertex on a surface.
    for shape in ["rectangle", "sphere", "disk"] {
        let lit = format!(
            "{CLOUD}\n[[shapes]]\ntype = \"{shape}\"\nto_world = {{ translate = [0, 3, 0] }}\n"
        );
        assert!(build(&lit, &[]).is_ok(), "{shape}");
        let emitting = format!("{lit}emitter = {{ radiance = [1, 1, 1] }}\n");
        assert!(build(&emitting, &[]).is_ok(), "{shape}");
        let e = build(&lit, &["integrator.shift=vertex"]).err().unwrap();
        assert!(e.contains("on surfaces is not built"), "{shape}: {e}");
    }
    for bsdf in ["plastic", "conductor", "dielectric"] {
        let smooth =
            format!("{CLOUD}\n[[shapes]]\ntype = \"rectangle\"\nbsdf = {{ type = \"{bsdf}\" }}\n");
        let e = build(&smooth, &[]).err().unwrap();
        assert!(e.contains("smooth (delta) lobe of shapes.0"), "{bsdf}: {e}");
        let rough = smooth.replace(bsdf, &format!("rough{bsdf}"));
        assert!(build(&rough, &[]).is_ok(), "rough{bsdf}");
    }
}

#[test]
fn restir_is_independent_of_the_thread_count() {
    let s = build(CLOUD, &[]).unwrap();
    let film = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let opts = RenderOptions::new(2, 5);
        pool.install(|| render(&s, &opts, &Progress::default()))
            .film
    };
    let (a, b) = (film(1), film(2));
    assert_eq!(a.sums, b.sums);
    assert_eq!(a.nan_samples + a.inf_samples, 0);
    assert!(a.image_mean()[0] > 0.0);
}

/// The primary-ray tables give marching's T̃ bit for bit, so a render
/// with them is the render without them: also when a still scene keeps its
/// tables from frame to frame, and when a moving camera must rebuild them
/// every frame (stale tables would change the image).
#[test]
fn primary_tables_change_no_bit_of_still_or_moving_sequences() {
    use fogbank_render::integrators::restir::frame::Sequence;
    use fogbank_render::integrators::IntegratorKind;
    let radiance = |text: &str, table: bool| {
        let set = [format!("integrator.primary_table={table}")];
        let desc = parse_scene(text, "test", &set).unwrap();
        let animated = text.contains("[animation]");
        let scenes: Vec<Scene> = (0..if animated { 3 } else { 1 })
            .map(|f| Scene::build_frame(desc.clone(), Path::new("."), f).unwrap())
            .collect();
        let restir: Vec<_> = scenes
            .iter()
            .map(|s| match &s.integrator {
                IntegratorKind::Restir(r) => r,
                _ => unreachable!(),
            })
            .collect();
        let mut seq = Sequence::new(restir[0], 7, 0);
        (0..3usize)
            .map(|f| {
                let (c, p) = if animated {
                    (f, f.saturating_sub(1))
                } else {
                    (0, 0)
                };
                let (cur, prev) = (
                    restir[c].data(&scenes[c].world),
                    restir[p].data(&scenes[p].world),
                );
                let out = seq.frame(&cur, &prev);
                out.radiance
                    .iter()
                    .map(|l| l.to_array().map(f32::to_bits))
                    .collect::<Vec<_>>()
            })
            .collect::<Vec<_>>()
    };
    let moving = format!(
        "{CLOUD}[animation]\nframes = 3\n[[animation.camera]]\nframe = 0\nfrom = [0.0, 0.2, 2.0]\n\
         [[animation.camera]]\nframe = 2\nfrom = [0.6, 0.0, 1.8]\n"
    );
    for text in [CLOUD, moving.as_str()] {
        let (with, without) = (radiance(text, true), radiance(text, false));
        assert!(with[2].iter().any(|p| p[0] != 0), "the volume is in view");
        assert_eq!(with, without);
    }
}

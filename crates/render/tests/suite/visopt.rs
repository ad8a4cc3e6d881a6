//! `visopt` (Lerzer and Dachsbacher 2025): with q = r = 0 it is
//! the unoptimised renderer (bit for bit against `optimise = false`, and
//! per pixel against `direct` under the z-test), with the defaults the image
//! differs (power); with its lists frozen and light rays unoptimised its
//! mean equals a deterministic evaluation of the same optimised image.

use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, render, Film, Progress, RenderOptions, Scene};
use std::path::Path;

const SCENE: &str = include_str!("../scenes/visopt_cloud.toml");

fn scene(extra: &[&str]) -> Scene {
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let desc = parse_scene(SCENE, "test", &extra).unwrap();
    Scene::build(desc, Path::new(".")).unwrap()
}

fn film(s: &Scene, spp: u32, seed: u32) -> Film {
    render(s, &RenderOptions::new(spp, seed), &Progress::default()).film
}

/// (max |z| over pixels, pooled z) of two renders' means.
fn z(a: &Film, b: &Film) -> (f64, f64) {
    let (ma, va, mb, vb) = (
        a.mean(),
        a.variance_of_mean(),
        b.mean(),
        b.variance_of_mean(),
    );
    let (mut max, mut diff, mut var) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..ma.len() {
        let d = (ma[i][0] - mb[i][0]) as f64;
        let v = (va[i][0] + vb[i][0]) as f64;
        if v > 0.0 {
            max = max.max(d.abs() / v.sqrt());
        } else {
            assert_eq!(d, 0.0, "pixel {i} differs with zero variance");
        }
        diff += d;
        var += v;
    }
    (max, diff / var.sqrt().max(1e-30))
}

#[test]
fn zero_weights_are_the_unoptimised_renderer() {
    let base = [
        "integrator.type=\"visopt\"",
        "integrator.shading=false",
        "integrator.light_samples=0",
    ];
    let with = |extra: &[&str]| scene(&[&base[..], extra].concat());
    let zero = film(&with(&["integrator.q=0.0", "integrator.r=0.0"]), 8, 1);
    let plain = film(&with(&["integrator.optimise=false"]), 8, 1);
    assert_eq!(zero.sums, plain.sums, "q = r = 0 must leave μ untouched");

    // Against `direct` (delta tracking, ratio-tracked NEE): same expectation.
    let spp = 256;
    let v = film(&with(&["integrator.q=0.0", "integrator.r=0.0"]), spp, 2);
    let d = film(
        &scene(&[
            "integrator.type=\"direct\"",
            "integrator.distance_sampler=\"delta_tracking\"",
            "integrator.estimator=\"ratio_tracking\"",
        ]),
        spp,
        3,
    );
    let (max, pooled) = z(&v, &d);
    assert!(
        max < 4.6 && pooled.abs() < 4.0,
        "visopt(q = r = 0) vs direct: max |z| {max}, pooled {pooled}"
    );

    // Power: the defaults change the image.
    let opt = film(&with(&[]), spp, 2);
    let (_, pooled) = z(&opt, &d);
    assert!(
        pooled.abs() > 6.0,
        "the optimisation does not show: pooled z {pooled}"
    );
}

/// The cloud grid of [`SCENE`], an analytic phantom (a sinusoidal field)
/// and a real MRI (nibabel's `anatomical.nii`, placed in millimetres).
fn unbiased_scenes() -> Vec<(&'static str, String)> {
    let sinusoid = SCENE.replace(
        "density = { procedural = \"cloud\", resolution = 24, seed = 3 }",
        "density = { procedural = \"sinusoid\", resolution = 24, value = 1.0, amplitude = 0.9 }",
    );
    let mri = format!(
        "[camera]\nfrom = [0.0, 30.0, 250.0]\nto = [1.0, -1.0, 7.0]\nfov = 40.0\nwidth = 12\nheight = 10\n\
         [[media]]\ndensity = {{ nifti = \"{}/../volume/tests/fixtures/sci/anatomical.nii\" }}\n\
         sigma_t_scale = 0.08\nalbedo = [0.9, 0.9, 0.9]\nfilter = \"trilinear\"\nprecision = \"f32\"\n\
         [[media.importance]]\nextinction = [0.03, 1e9]\n\
         [[lights]]\ntype = \"point\"\nposition = [150.0, 150.0, 100.0]\nintensity = [3e5, 3e5, 3e5]\n\
         [render]\npixel_jitter = false\n",
        env!("CARGO_MANIFEST_DIR")
    );
    vec![
        ("cloud grid", SCENE.to_string()),
        ("analytic phantom", sinusoid),
        ("real MRI", mri),
    ]
}

fn scene_from(text: &str, extra: &[&str]) -> Scene {
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let desc = parse_scene(text, "test", &extra).unwrap();
    Scene::build(desc, Path::new(".")).unwrap()
}

#[test]
fn frozen_lists_give_an_unbiased_estimate_of_the_optimised_image() {
    for (name, text) in unbiased_scenes() {
        for shading in ["false", "true"] {
            check_unbiased(name, &text, shading);
        }
    }
}

/// The visopt mean at 512 spp against the deterministic evaluation of the
/// same optimised image; for the cloud also the power check against the
/// unoptimised expectation.
fn check_unbiased(name: &str, text: &str, shading: &str) {
    let scene = |extra: &[&str]| scene_from(text, extra);
    let s = scene(&[
        "integrator.type=\"visopt\"",
        "integrator.light_samples=0",
        &format!("integrator.shading={shading}"),
    ]);
    let IntegratorKind::VisOpt(v) = &s.integrator else {
        panic!()
    };
    let f = film(&s, 512, 4);
    let (w, h) = (s.camera.width, s.camera.height);
    // In [−1, 1]³ units.
    let (step, shadow_step) = (1.0 / 2048.0, 1.0 / 128.0);
    let reference: Vec<f32> = (0..w * h)
        .map(|i| {
            v.expected_pixel(&s.world, i % w, i / w, step, shadow_step)
                .unwrap()
                .x
        })
        .collect();
    let (mean, var) = (f.mean(), f.variance_of_mean());
    // Halving the steps changes nothing measurable: far below the
    // Monte Carlo error of the pixel.
    for i in [(h / 2 * w + w / 2) as usize, (h / 3 * w + w / 3) as usize] {
        let fine = v
            .expected_pixel(
                &s.world,
                i as u32 % w,
                i as u32 / w,
                step / 2.0,
                shadow_step / 2.0,
            )
            .unwrap()
            .x;
        let se = var[i][0].sqrt();
        assert!(
            (fine - reference[i]).abs() < 0.1 * se,
            "pixel {i}: {} vs {fine} (se {se})",
            reference[i]
        );
    }
    let (mut max, mut diff, mut sum_var) = (0.0f64, 0.0f64, 0.0f64);
    let top = reference.iter().copied().fold(0.0f32, f32::max);
    for i in 0..reference.len() {
        let d = (mean[i][0] - reference[i]) as f64;
        if var[i][0] == 0.0 {
            // No collision in any sample (a grazing ray): the estimate
            // cannot be tested there, and the expectation must be tiny.
            // (With n samples and hits worth about `top`, an expectation
            // above 5·top/n is missed with probability below e^{-5}.)
            assert!(
                reference[i] < 5.0 * top / 512.0,
                "pixel {i}: variance 0 but expected {}",
                reference[i]
            );
            continue;
        }
        let v = var[i][0] as f64 + (1e-6 * reference[i] as f64).powi(2);
        max = max.max(d.abs() / v.sqrt());
        diff += d;
        sum_var += v;
    }
    let pooled = diff / sum_var.sqrt();
    assert!(
        max < 4.6 && pooled.abs() < 4.0,
        "{name}, shading {shading}: max |z| {max}, pooled {pooled}"
    );
    assert!(
        reference.iter().any(|&r| r > 0.01),
        "{name}: the image is black"
    );
    if name != "cloud grid" {
        return;
    }
    // Power: the film is far from the *unoptimised* expectation.
    let plain = scene(&[
        "integrator.type=\"visopt\"",
        "integrator.light_samples=0",
        "integrator.optimise=false",
        &format!("integrator.shading={shading}"),
    ]);
    let IntegratorKind::VisOpt(pv) = &plain.integrator else {
        panic!()
    };
    let off: f64 = (0..w * h)
        .map(|i| {
            (mean[i as usize][0]
                - pv.expected_pixel(&plain.world, i % w, i / w, step, shadow_step)
                    .unwrap()
                    .x) as f64
        })
        .sum();
    assert!(
        off / sum_var.sqrt() < -3.5,
        "shading {shading}: optimised vs plain expectation, pooled z {}",
        off / sum_var.sqrt()
    );
}

#[test]
fn settings_are_checked() {
    let err = |extra: &[&str]| {
        let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
        let desc = parse_scene(SCENE, "test", &extra);
        match desc {
            Err(e) => e.to_string(),
            Ok(d) => Scene::build(d, Path::new("."))
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
        }
    };
    assert!(err(&["integrator.type=\"visopt\"", "integrator.p=0.0"]).contains("integrator.p"));
    assert!(err(&[
        "integrator.type=\"visopt\"",
        "integrator.scattering=\"twice\""
    ])
    .contains("integrator.scattering"));
    assert!(
        err(&["integrator.type=\"visopt\"", "integrator.samples=0"]).contains("integrator.samples")
    );
}

/// Acceptance 4 (second half): lengths in h are in the medium's normalised
/// [−1, 1]³ units, so a volume and a copy scaled by 100 (a head in mm and
/// in metres: σ_t, the extinction criterion and the camera scaled to
/// match) get the same lists and the same μ'/μ at corresponding points, and
/// render alike.
#[test]
fn a_scaled_copy_is_optimised_alike() {
    let build = |k: f32| {
        let text = SCENE
            .replace(
                "from = [0.0, 0.2, 2.0]",
                &format!("from = [0.0, {}, {}]", 0.2 * k, 2.0 * k),
            )
            .replace(
                "sigma_t_scale = 12.0",
                &format!("sigma_t_scale = {}\nto_world = {{ scale = {k} }}", 12.0 / k),
            )
            .replace(
                "extinction = [4.0, 1e9]",
                &format!("extinction = [{}, 1e9]", 4.0 / k),
            )
            .replace(
                "position = [1.5, 1.5, 1.0]",
                &format!("position = [{}, {}, {}]", 1.5 * k, 1.5 * k, 1.0 * k),
            )
            .replace(
                "intensity = [6.0, 6.0, 6.0]",
                &format!("intensity = [{0}, {0}, {0}]", 6.0 * k * k),
            );
        let desc = parse_scene(&text, "test", &["integrator.type=\"visopt\"".to_string()]).unwrap();
        Scene::build(desc, Path::new(".")).unwrap()
    };
    let (a, b) = (build(1.0), build(100.0));
    let (IntegratorKind::VisOpt(va), IntegratorKind::VisOpt(vb)) = (&a.integrator, &b.integrator)
    else {
        panic!()
    };
    assert!((va.unit / vb.unit - 100.0).abs() < 1e-3);
    let (la, lb) = (va.lists(&a.world), vb.lists(&b.world));
    let mut compared = 0;
    for y in 0..a.camera.height {
        for x in 0..a.camera.width {
            let ((sa, ka, lena), (sb, kb, lenb)) = (la.get(x, y), lb.get(x, y));
            assert!(
                (lena - lenb).abs() < 1e-4 * lena.max(1.0),
                "pixel {x},{y}: L {lena} vs {lenb}"
            );
            assert!(
                (ka - kb).abs() < 1e-3 * ka.max(1e-3),
                "pixel {x},{y}: K(z) {ka} vs {kb}"
            );
            assert_eq!(sa.len(), sb.len(), "pixel {x},{y}");
            for (u, v) in sa.iter().zip(sb) {
                assert!(
                    (u.t - v.t).abs() < 1e-3 && u.k == v.k,
                    "pixel {x},{y}: {u:?} vs {v:?}"
                );
            }
            compared += sa.len();
        }
    }
    assert!(compared > 50, "only {compared} entries");
    let (fa, fb) = (film(&a, 64, 9), film(&b, 64, 9));
    let (max, pooled) = z(&fa, &fb);
    assert!(
        max < 4.6 && pooled.abs() < 4.0,
        "scaled copy: max |z| {max}, pooled {pooled}"
    );
}

/// Pre-interpolative importance (Figs. 3, 11) classifies voxel centres:
/// there it equals the post-interpolative importance; between voxels the
/// trilinear variant blends values the rules never give (e.g. ½), and the
/// lists merge them only within 10⁻³.
#[test]
fn pre_interpolative_importance_classifies_voxel_centres() {
    let build = |pre: &str| {
        let text = SCENE.replace(
            "[[media.importance]]",
            &format!("{pre}\n[[media.importance]]"),
        );
        let desc = parse_scene(&text, "test", &["integrator.type=\"visopt\"".to_string()]).unwrap();
        Scene::build(desc, Path::new(".")).unwrap()
    };
    let post = build("");
    let pre = build("importance_pre = { filter = \"trilinear\" }");
    let (mp, mq) = (&post.world.media[0], &pre.world.media[0]);
    let xf = mp.medium.index_to_world;
    let at = |m: &fogbank_render::world::medium::SceneMedium, p: fogbank_math::Vec3| {
        fogbank_render::integrators::visopt::optimised::importance_at(m, p, m.sigma_t_smooth(p))
    };
    let (mut between, mut important) = (0, 0);
    for i in 0..23 {
        for (j, k) in [(12, 12), (10, 13), (11, 9)] {
            let world = |x: f64| {
                xf.transform_point3(glam::DVec3::new(x, j as f64 + 0.5, k as f64 + 0.5))
                    .as_vec3()
            };
            let c = world(i as f64 + 0.5);
            // (The world → index round trip lands within an ulp of the centre.)
            assert!((at(mp, c) - at(mq, c)).abs() < 1e-5, "voxel {i},{j},{k}");
            important += (at(mp, c) > 0.0) as u32;
            let v = at(mq, world(i as f64 + 1.0));
            between += (v > 0.0 && v < 1.0) as u32;
        }
    }
    assert!(
        important > 3,
        "only {important} important voxels on the lines"
    );
    assert!(between > 0, "no blended importance between voxels");
    assert_eq!(pre.world.media[0].importance.tolerance(), 1e-3);
    assert_eq!(post.world.media[0].importance.tolerance(), 0.0);
}

//! `volpath` with surfaces against analytic answers: a lit
//! diffuse plane, a convex object under a uniform sky, irradiance from a
//! rectangular area light, and emitting furnaces (closed boxes and
//! spheres, with and without a medium inside) whose radiance is
//! Le / (1 − ρ).

use fogbank_render::{parse_scene, render, Film, Progress, RenderOptions, Scene, SceneError};
use std::path::Path;

fn build(text: &str) -> Scene {
    build_with(text, &[])
}

/// Why the scene of `text`, which parses, does not build.
fn build_error(text: &str) -> SceneError {
    Scene::build(parse_scene(text, "t", &[]).unwrap(), Path::new("."))
        .err()
        .unwrap()
}

/// A scene from `text` with `--set` edits.
fn build_with(text: &str, set: &[&str]) -> Scene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    Scene::build(parse_scene(text, "test", &set).unwrap(), Path::new(".")).unwrap()
}

/// A diffuse plane (ρ = 0.6) under a directional light (E = 2, cos θ = 0.8).
const PLANE: &str = include_str!("../scenes/diffuse_plane.toml");

fn film(s: &Scene, spp: u32) -> Film {
    render(s, &RenderOptions::new(spp, 3), &Progress::default()).film
}

/// Mean and standard error of channel 0 over the pixels `keep` accepts,
/// pooling every sample.
fn pooled(f: &Film, keep: impl Fn(usize) -> bool) -> (f64, f64) {
    let (mut n, mut sum, mut sum2) = (0.0f64, 0.0f64, 0.0f64);
    for i in (0..f.sums.len()).filter(|&i| keep(i)) {
        n += f.count[i] as f64;
        sum += f.sum(i)[0];
        sum2 += f.sum_sq(i)[0];
    }
    let mean = sum / n;
    (mean, ((sum2 / n - mean * mean) / n).sqrt())
}

/// A diffuse plane under a directional light: every pixel that sees it
/// shows ρ/π · E cos θ exactly (NEE toward a delta light is deterministic
/// and the BSDF-sampled direction finds nothing).
#[test]
fn diffuse_plane_under_a_directional_light() {
    let s = build_with(
        PLANE,
        &["integrator.type=volpath", "integrator.max_depth=1"],
    );
    let f = film(&s, 4);
    let expected = 0.6 / std::f64::consts::PI * 2.0 * 0.8;
    for i in 0..f.sums.len() {
        let v = f.sum(i)[0] / f.count[i] as f64;
        assert!((v - expected).abs() < 1e-5, "pixel {i}: {v} vs {expected}");
    }
}

/// A convex diffuse cube under a uniform sky of radiance 1: light that
/// leaves it never returns, so every pixel on it shows ρ (light sampling
/// and BSDF sampling share the sky by MIS).
#[test]
fn convex_cube_under_a_uniform_sky_reflects_rho() {
    let s = build(
        "[camera]\nfrom = [3, -4, 2.5]\nto = [0, 0, 0]\nwidth = 16\nheight = 16\nfov = 22\n\
         [[shapes]]\ntype = \"cube\"\nto_world = { rotate = [0, 0, 1, 20] }\nbsdf = { type = \"diffuse\", reflectance = 0.7 }\n\
         [[lights]]\ntype = \"constant\"\nradiance = [1, 1, 1]\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 4\n",
    );
    let f = film(&s, 64);
    // Pixels that see the sky read exactly 1; those on the cube average ρ.
    let on_cube = |i: usize| f.sum(i)[0] / (f.count[i] as f64) < 0.999;
    let cube_pixels = (0..f.sums.len()).filter(|&i| on_cube(i)).count();
    assert!(cube_pixels > 60, "{cube_pixels} pixels see the cube");
    let (mean, se) = pooled(&f, |i| {
        let x = (i % 16) as i32 - 8;
        let y = (i / 16) as i32 - 8;
        // The cube's core, away from edge pixels that mix sky and cube.
        x.abs() <= 2 && y.abs() <= 2
    });
    assert!((mean - 0.7).abs() < 4.0 * se + 1e-4, "{mean} ± {se}");
}

/// Irradiance at the centre below a square emitter (side 2a, height h,
/// facing down): E = 4 π L F(a/h, a/h) with the corner form factor
/// F(X, Y) = (X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))) / 2π.
#[test]
fn square_area_light_irradiance() {
    let (a, h, le, rho) = (0.5f64, 1.0f64, 3.0f64, 0.5f64);
    let s = build(&format!(
        "[camera]\nfrom = [0, -3, 0.4]\nto = [0, 0, 0]\nwidth = 1\nheight = 1\nfov = 5\n\
         [render]\npixel_jitter = false\n\
         [[shapes]]\ntype = \"rectangle\"\nto_world = {{ scale = 10 }}\nbsdf = {{ type = \"diffuse\", reflectance = {rho} }}\n\
         [[shapes]]\ntype = \"rectangle\"\nflip_normals = true\nto_world = {{ scale = {a}, translate = [0, 0, {h}] }}\n\
         bsdf = {{ type = \"diffuse\", reflectance = 0 }}\nemitter = {{ radiance = [{le}, {le}, {le}] }}\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 1\n"
    ));
    let (x, y) = (a / h, a / h);
    let f = (x / (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
        + y / (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan())
        / (2.0 * std::f64::consts::PI);
    let irradiance = 4.0 * std::f64::consts::PI * le * f;
    let expected = rho / std::f64::consts::PI * irradiance;
    let film = film(&s, 40_000);
    let (mean, se) = pooled(&film, |_| true);
    assert!(
        (mean - expected).abs() < 4.0 * se && se < 0.01 * expected,
        "{mean} ± {se} vs {expected}"
    );
}

/// Inside a closed box or sphere whose walls emit Le and reflect ρ (diffuse), the
/// radiance is Le Σ_k ρ^k = Le (1 − ρ^(n+1)) / (1 − ρ) for paths of up to
/// n vertices: emission seen directly, then one more bounce per vertex,
/// each found by light sampling and by BSDF sampling together (MIS).
/// A non-absorbing medium inside leaves the uniform, isotropic field as it
/// is (with unlimited depth).
#[test]
fn emitting_furnace_box_and_sphere_with_and_without_a_medium() {
    // A cube, and an analytic sphere emitting inward (sampled by area from
    // inside, sphere.rs).
    for shape in ["cube", "sphere"] {
        let walls = format!(
            "[camera]\nfrom = [0.1, -0.5, 0.2]\nto = [0, 1, 0]\nwidth = 8\nheight = 8\nfov = 60\n\
             [[shapes]]\ntype = \"{shape}\"\nflip_normals = true\n\
             bsdf = {{ type = \"diffuse\", reflectance = 0.5 }}\nemitter = {{ radiance = [1, 1, 1] }}\n"
        );
        for (extra, depth, expected, spp) in [
            ("", 3, (1.0 - 0.5f64.powi(4)) / 0.5, 256),
            (
                "[[media]]\ndensity = { procedural = \"constant\", resolution = 4 }\nsigma_t_scale = 1.5\n\
                 albedo = [1, 1, 1]\nto_world = { scale = 1.9 }\n",
                100_000,
                2.0,
                2048,
            ),
        ] {
            let s = build(&format!(
                "{walls}{extra}[integrator]\ntype = \"volpath\"\nmax_depth = {depth}\n"
            ));
            let f = film(&s, spp);
            let (mean, se) = pooled(&f, |_| true);
            assert!(
                (mean - expected).abs() < 4.0 * se && se < 0.01,
                "{shape}, depth {depth}: {mean} ± {se} vs {expected}"
            );
            assert_eq!(f.nan_samples + f.inf_samples, 0);
        }
    }
}

/// A bad shape names its key (integrators without surface rules:
/// suite/occluders.rs).
#[test]
fn shape_errors_name_the_key() {
    let base = "[[shapes]]\ntype = \"cube\"\n";
    let e = parse_scene(&format!("{base}colour = 1\n"), "t", &[]).unwrap_err();
    assert!(e.0.contains("colour"), "{e}");
    let e = build_error("[[shapes]]\ntype = \"obj\"\n[integrator]\ntype = \"volpath\"\n");
    assert!(e.0.contains("shapes.0") && e.0.contains("file"), "{e}");
    let e = build_error(
        "[[shapes]]\ntype = \"obj\"\nfile = \"missing.obj\"\n[integrator]\ntype = \"volpath\"\n",
    );
    assert!(
        e.0.contains("shapes.0") && e.0.contains("missing.obj"),
        "{e}"
    );
    // Analytic shapes: a sphere has one radius; they have no vertices.
    let build_err = |shape: &str| {
        build_error(&format!(
            "[[shapes]]\n{shape}\n[integrator]\ntype = \"volpath\"\n"
        ))
        .0
    };
    let e = build_err("type = \"sphere\"\nto_world = { scale = [1, 2, 1] }");
    assert!(
        e.contains("shapes.0.to_world") && e.contains("uniform scale"),
        "{e}"
    );
    let e = build_err("type = \"disk\"\nface_normals = true");
    assert!(
        e.contains("shapes.0.face_normals") && e.contains("disk"),
        "{e}"
    );
}

/// A medium bounded by a null cube exists only inside it: its box is
/// larger than the cube, yet light crosses only the cube's chord — seen
/// from outside, from a camera inside, and by shadow rays toward a
/// directional light (the medium absorbs only: the mean is the
/// transmittance).
#[test]
fn null_bounded_medium_exists_only_inside_its_shape() {
    let sigma = 0.7f64;
    let medium = format!(
        "[[media]]\ndensity = {{ procedural = \"constant\", resolution = 4 }}\nsigma_t_scale = {sigma}\n\
         albedo = [0, 0, 0]\nto_world = {{ scale = 3 }}\n\
         [[shapes]]\ntype = \"cube\"\nbsdf = {{ type = \"null\" }}\ninterior = 0\n"
    );
    let view = |from: &str, to: &str, extra: &str| {
        build(&format!(
            "[camera]\nfrom = {from}\nto = {to}\nup = [0, 0, 1]\nwidth = 1\nheight = 1\nfov = 1\n\
             [render]\npixel_jitter = false\n{medium}{extra}\
             [integrator]\ntype = \"volpath\"\nmax_depth = 1\n"
        ))
    };
    let sky = "[[lights]]\ntype = \"constant\"\nradiance = [1, 1, 1]\n";
    let ground = "[[shapes]]\ntype = \"rectangle\"\nto_world = { translate = [0, 0, -1.2], scale = 10 }\n\
                  bsdf = { type = \"diffuse\", reflectance = 0.5 }\n\
                  [[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nirradiance = [1, 1, 1]\n";
    for (what, scene, expected) in [
        (
            "through",
            view("[0, -5, 0]", "[0, 0, 0]", sky),
            (-2.0 * sigma).exp(),
        ),
        (
            "from inside",
            view("[0, 0, 0]", "[1, 0, 0]", sky),
            (-sigma).exp(),
        ),
        (
            "shadow",
            view("[0, -5, -1.1]", "[0, 0, -1.2]", ground),
            0.5 / std::f64::consts::PI * (-2.0 * sigma).exp(),
        ),
    ] {
        let f = film(&scene, 60_000);
        let (mean, se) = pooled(&f, |_| true);
        assert!(
            (mean - expected).abs() < 4.0 * se + 1e-6 && se < 0.01 * expected,
            "{what}: {mean} ± {se} vs {expected}"
        );
    }
}

/// Lossless surfaces in a uniform sky: smooth glass (with a scattering,
/// non-absorbing medium inside) and a thin glass sheet neither create nor
/// destroy light, so every pixel reads the sky's radiance 1 — through
/// refraction, total internal reflection, the medium switch at the glass
/// and the delta lobes' MIS weights.
#[test]
fn lossless_glass_in_a_uniform_sky_is_invisible() {
    let s = build(
        "[camera]\nfrom = [0, -4, 1]\nto = [0, 0, 0]\nup = [0, 0, 1]\nwidth = 12\nheight = 12\nfov = 40\n\
         [[lights]]\ntype = \"constant\"\nradiance = [1, 1, 1]\n\
         [[media]]\ndensity = { procedural = \"constant\", resolution = 4 }\nsigma_t_scale = 2\n\
         albedo = [1, 1, 1]\nphase = { type = \"hg\", g = 0.5 }\nto_world = { scale = 2.2 }\n\
         [[shapes]]\ntype = \"sphere\"\nbsdf = { type = \"dielectric\", int_ior = 1.5, ext_ior = 1 }\ninterior = 0\n\
         [[shapes]]\ntype = \"rectangle\"\nto_world = { translate = [0, -2, 0], rotate = [1, 0, 0, 70], scale = 0.8 }\n\
         bsdf = { type = \"thindielectric\" }\n\
         [integrator]\ntype = \"volpath\"\nmax_depth = 100000\n",
    );
    let f = film(&s, 256);
    let (mean, se) = pooled(&f, |_| true);
    assert!((mean - 1.0).abs() < 4.0 * se && se < 0.01, "{mean} ± {se}");
    assert_eq!(f.nan_samples + f.inf_samples, 0);
}

/// `direct` and `transmittance` see surfaces too: `direct` lights them
/// (it is `volpath` with one vertex), `transmittance` is hidden by them
/// and counts a bounded medium only inside its shape.
#[test]
fn direct_and_transmittance_see_surfaces() {
    let s = build_with(
        PLANE,
        &[
            "camera.width=4",
            "camera.height=4",
            "integrator.type=direct",
        ],
    );
    let f = film(&s, 2);
    let expected = 0.6 / std::f64::consts::PI * 2.0 * 0.8;
    assert!((f.sum(5)[0] / f.count[5] as f64 - expected).abs() < 1e-5);
    let sigma = 0.7f64;
    let s = build(&format!(
        "[camera]\nfrom = [0, -5, 0]\nto = [0, 0, 0]\nup = [0, 0, 1]\nwidth = 1\nheight = 1\nfov = 1\n\
         [render]\npixel_jitter = false\n\
         [[media]]\ndensity = {{ procedural = \"constant\", resolution = 4 }}\nsigma_t_scale = {sigma}\nto_world = {{ scale = 3 }}\n\
         [[shapes]]\ntype = \"cube\"\nbsdf = {{ type = \"null\" }}\ninterior = 0\n\
         [integrator]\ntype = \"transmittance\"\n"
    ));
    let (mean, se) = pooled(&film(&s, 20_000), |_| true);
    let expected = (-2.0 * sigma).exp();
    assert!(
        (mean - expected).abs() < 4.0 * se + 1e-6,
        "{mean} ± {se} vs {expected}"
    );
    let s = build(
        "[camera]\nfrom = [0, -5, 0]\nto = [0, 0, 0]\nup = [0, 0, 1]\nwidth = 1\nheight = 1\nfov = 1\n\
         [render]\npixel_jitter = false\n[[shapes]]\ntype = \"cube\"\n",
    );
    assert_eq!(pooled(&film(&s, 4), |_| true).0, 0.0);
}

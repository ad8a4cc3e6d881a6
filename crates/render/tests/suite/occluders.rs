//! Integrators without surface rules yet (`point_mis`, `visopt`, `ament`;
//! `restir` in eval/tests/restir_unbiased_test.rs) see shapes as opaque
//! black occluders (`shared/occluders.rs`): their images
//! agree per pixel with `direct`'s of the same scene, whose black BSDFs
//! reflect nothing, and scenes whose shapes pass light are refused.

use fogbank_render::{parse_scene, render, Film, Progress, RenderOptions, Scene};
use std::path::Path;

/// A cloud under a point light; one black square hides the left of the
/// view, another shadows part of the cloud from the light.
const MEDIUM: &str = "[camera]\nfrom = [0.0, 0.0, 1.4]\nwidth = 16\nheight = 12\nfov = 30.0\n\
    [[media]]\ndensity = { procedural = \"cloud\", resolution = 32, seed = 3 }\n\
    sigma_t_scale = 12.0\nalbedo = [0.9, 0.9, 0.9]\nphase = { type = \"hg\", g = 0.3 }\n\
    filter = \"nearest\"\n\
    [[lights]]\ntype = \"point\"\nposition = [0.1, 0.6, 0.1]\nintensity = [0.8, 0.8, 0.8]\n\
    [render]\npixel_jitter = false\n";
const SHAPES: &str =
    "[[shapes]]\ntype = \"rectangle\"\nto_world = { translate = [-0.2, 0.0, 0.7], scale = 0.12 }\n\
    bsdf = { type = \"diffuse\", reflectance = 0.0 }\n\
    [[shapes]]\ntype = \"rectangle\"\n\
    to_world = { translate = [0.2, 0.3, 0.0], rotate = [1.0, 0.0, 0.0, -90.0], scale = 0.2 }\n\
    bsdf = { type = \"diffuse\", reflectance = 0.0 }\n";

fn try_build(text: &str, integrator: &[&str]) -> Result<Scene, String> {
    let set: Vec<String> = integrator.iter().map(|s| s.to_string()).collect();
    parse_scene(text, "test", &set)
        .and_then(|d| Scene::build(d, Path::new(".")))
        .map_err(|e| e.0)
}

fn film(text: &str, integrator: &[&str], spp: u32, seed: u32) -> Film {
    let s = try_build(text, integrator).unwrap();
    let f = render(&s, &RenderOptions::new(spp, seed), &Progress::default()).film;
    assert_eq!(f.nan_samples + f.inf_samples, 0, "{integrator:?}");
    f
}

/// Per pixel (green): no |z| beyond 5 and a pooled |z| below 4 over the
/// lit pixels; returns the pooled z.
fn agree(label: &str, a: &Film, b: &Film) -> f64 {
    let d: Vec<(f64, f64)> = a
        .mean_difference(b, 1)
        .into_iter()
        .filter(|d| d.1 > 0.0)
        .collect();
    assert!(d.len() >= 60, "{label}: only {} lit pixels", d.len());
    let max = d
        .iter()
        .map(|(x, v)| (x / v.sqrt()).abs())
        .fold(0.0, f64::max);
    let pooled = d.iter().map(|x| x.0).sum::<f64>() / d.iter().map(|x| x.1).sum::<f64>().sqrt();
    eprintln!("{label}: max |z| {max:.2}, pooled z {pooled:.2}");
    assert!(
        max < 5.0 && pooled.abs() < 4.0,
        "{label}: max |z| {max:.2}, pooled {pooled:.2}"
    );
    pooled
}

fn scene() -> String {
    format!("{MEDIUM}{SHAPES}")
}

#[test]
fn point_mis_and_visopt_with_occluders_match_direct() {
    let reference = film(&scene(), &["integrator.type=direct"], 2048, 1);
    for strategy in ["mis_jackknife", "equiangular"] {
        let s = format!("integrator.strategy={strategy}");
        let f = film(&scene(), &["integrator.type=point_mis", &s], 2048, 2);
        agree(&format!("point_mis {strategy}"), &reference, &f);
    }
    let f = film(
        &scene(),
        &["integrator.type=visopt", "integrator.optimise=false"],
        2048,
        3,
    );
    agree("visopt unoptimised", &reference, &f);
    // The occluders matter: without them the image is brighter.
    let open = film(MEDIUM, &["integrator.type=point_mis"], 1024, 4);
    let (mo, m) = (open.image_mean()[1], reference.image_mean()[1]);
    assert!(mo > 1.1 * m, "without shapes {mo}, with {m}");
}

#[test]
fn ament_marches_up_to_the_first_surface() {
    let with = film(&scene(), &["integrator.type=ament"], 1, 0);
    let without = film(MEDIUM, &["integrator.type=ament"], 1, 0);
    let (a, b) = (with.mean(), without.mean());
    let w = with.width as usize;
    // Pixel (2, 6) lies behind the front square: black; without it, lit.
    assert_eq!(a[6 * w + 2], [0.0; 3]);
    assert!(b[6 * w + 2][1] > 0.0);
    // The other square shadows part of the cloud and brightens nothing.
    assert!(a.iter().zip(&b).all(|(x, y)| x[1] <= y[1] + 1e-6));
    let (sa, sb): (f32, f32) = (a.iter().map(|p| p[1]).sum(), b.iter().map(|p| p[1]).sum());
    assert!(sa < 0.9 * sb, "{sa} vs {sb}");
}

#[test]
fn shapes_that_pass_light_are_refused() {
    let bounding = format!(
        "{MEDIUM}[[shapes]]\ntype = \"cube\"\nbsdf = {{ type = \"null\" }}\ninterior = 0\nto_world = {{ scale = 0.3 }}\n"
    );
    let thin = format!(
        "{MEDIUM}[[shapes]]\ntype = \"rectangle\"\nbsdf = {{ type = \"thindielectric\" }}\nto_world = {{ translate = [0.0, 0.0, 0.8], scale = 0.1 }}\n"
    );
    for integrator in ["point_mis", "visopt", "ament", "restir"] {
        let set = format!("integrator.type={integrator}");
        for text in [&bounding, &thin] {
            let e = try_build(text, &[&set]).err().unwrap();
            assert!(
                e.contains(integrator) && e.contains("occluders"),
                "{integrator}: {e}"
            );
        }
        // A null shape that bounds nothing is invisible and passes.
        let null = format!("{MEDIUM}[[shapes]]\ntype = \"cube\"\nbsdf = {{ type = \"null\" }}\n");
        try_build(&null, &[&set]).unwrap();
    }
}

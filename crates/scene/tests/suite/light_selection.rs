//! Light selection on a Mitsuba 3 scene: the strategies agree.

/// The street of 3200 emitting triangles (`scenes/street`) rendered with
/// lights picked by power and through the light BVH: the same image, per
/// pixel and on average (the mean z over all pixels catches a bias that
/// no single pixel shows: with the BVH's pmf in MIS weights halved, every
/// pixel passed and the mean z was −0.84 over 2304 pixels, 40 σ).
#[test]
fn light_bvh_and_power_selection_render_the_same_street() {
    use fogbank_image::metrics::ztest::ztest;
    use fogbank_render::{render, Progress, RenderOptions};
    use fogbank_scene::load_scene;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/street/window_street.xml");
    let image = |selection: &str, seed: u32| {
        let overrides = [
            "camera.width=48".to_string(),
            "camera.height=27".to_string(),
            format!("render.light_sampler={selection}"),
        ];
        let scene = load_scene(Some(&path), &overrides).unwrap();
        let opts = RenderOptions::new(256, seed);
        render(&scene, &opts, &Progress::default())
            .film
            .mean_image()
    };
    let z = ztest(&image("power", 1), &image("bvh", 2)).unwrap();
    let bound = 5.0 / (z.tests as f64 / 3.0).sqrt();
    assert!(
        z.pass && z.mean_z.iter().all(|m| m.abs() < bound),
        "{} pixels fail (max |z| {:.2}), mean z {:?} (bound {bound:.3})",
        z.failing_pixels,
        z.max_abs_z,
        z.mean_z
    );
}

//! Bit-identical renders of one medium read two ways (a file and its
//! conversion, a medium and its export): the transmittance image and the
//! comparison that refuses a blank view.

use fogbank_render::{render, Progress, RenderOptions, Scene, SceneDesc};
use std::path::Path;

/// The transmittance image of `desc` (4 spp, a fixed seed).
pub fn transmittance_image(desc: SceneDesc) -> Vec<[f32; 3]> {
    let scene = Scene::build(desc, Path::new(".")).unwrap();
    render(&scene, &RenderOptions::new(4, 7), &Progress::default())
        .film
        .mean()
}

/// Bit-identical images, and not a blank one.
pub fn assert_same_image(a: &[[f32; 3]], b: &[[f32; 3]], what: &str) {
    let bits =
        |img: &[[f32; 3]]| -> Vec<u32> { img.iter().flatten().map(|v| v.to_bits()).collect() };
    assert!(bits(a) == bits(b), "{what}: images differ");
    let lo = a.iter().flatten().fold(f32::MAX, |m, &v| m.min(v));
    assert!(lo < 0.9, "{what}: the medium is not in view (min {lo})");
}

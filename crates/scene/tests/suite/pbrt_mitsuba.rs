//! pbrt-v4 scenes against Mitsuba 3 and against fogbank's own TOML: each
//! `scenes/pbrt/NAME.pbrt` has a Mitsuba 3 twin written by hand
//! (`scenes/pbrt/mitsuba/NAME.xml`) whose `scalar_rgb` reference,
//! mirrored left-right because pbrt's look-at frame is left-handed, is
//! `scenes/pbrt/refs/NAME.exr` (`tools/mitsuba_refs.py --pbrt`), and a
//! TOML twin written by hand (`scenes/pbrt/NAME.toml`). fogbank's render
//! of the `.pbrt` must pass the Mitsuba agreement criteria of
//! `suite/mitsuba.rs` (per-pixel z-test, image means within 1 %, 8×8 block
//! means within 2 %), and the per-pixel z-test against an independent
//! render (another seed) of the TOML twin.
//!
//! Together the scenes cover every pbrt medium type — `homogeneous` (as
//! the camera's medium and behind a dielectric), `uniformgrid`, `rgbgrid`,
//! `nanovdb` and `cloud` — and every light type fogbank maps: `point`,
//! `spot`, `distant`, uniform and image (equal-area octahedral) `infinite`
//! and `diffuse` area lights; `interface` materials, `MediumInterface` on
//! shapes and before the camera, and shapes without media keeping the
//! ray's medium. `scenes/pbrt/README.md` lists them.

use fogbank_image::metrics::ztest::ztest;
use fogbank_render::{render, Film, Progress, RenderOptions};
use fogbank_scene::load_scene;

use crate::support::mitsuba_agreement;
use mitsuba_agreement::{assert_agrees_in, pbrt_scenes, spp_for_in};

fn render_file(file: &str, spp: u32, seed: u32) -> Film {
    let scene = load_scene(Some(&pbrt_scenes().join(file)), &[]).unwrap();
    render(&scene, &RenderOptions::new(spp, seed), &Progress::default()).film
}

fn agree(name: &str) {
    let spp = spp_for_in(&pbrt_scenes(), name);
    let film = render_file(&format!("{name}.pbrt"), spp, 7);
    assert_agrees_in(&pbrt_scenes(), name, &film);
    let twin = render_file(&format!("{name}.toml"), spp, 8);
    let z = ztest(&film.mean_image(), &twin.mean_image()).unwrap();
    assert!(
        z.pass,
        "{name}: the pbrt scene and its TOML twin differ in {} pixels (max |z| {:.2} at {:?}); mean z {:?}",
        z.failing_pixels, z.max_abs_z, z.max_abs_z_pixel, z.mean_z
    );
}

#[test]
fn camera_in_fog_with_point_and_spot_lights_agrees_with_mitsuba() {
    agree("fog_room");
}

#[test]
fn nanovdb_medium_under_sun_and_sky_agrees_with_mitsuba() {
    agree("nanovdb_sun");
}

#[test]
fn uniform_grid_medium_lit_by_an_area_light_agrees_with_mitsuba() {
    agree("uniformgrid_area");
}

#[test]
fn homogeneous_medium_behind_a_dielectric_agrees_with_mitsuba() {
    agree("glass_fog");
}

#[test]
fn rgb_grid_medium_under_an_octahedral_image_sky_agrees_with_mitsuba() {
    agree("rgbgrid_envmap");
}

#[test]
fn procedural_cloud_medium_agrees_with_mitsuba() {
    agree("cloud_distant");
}

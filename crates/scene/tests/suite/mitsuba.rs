//! Mitsuba 3 XML scenes: fogbank renders `scenes/mitsuba/*.xml` as they
//! are and must agree with Mitsuba 3 `scalar_rgb` references of the same
//! files (made by `tools/mitsuba_refs.py` with 2.5·10⁷ samples and
//! per-pixel variance): Mitsuba's own render-test criterion
//! (Šidák-corrected per-pixel z-test at α = 0.01) plus each channel's image
//! mean within 1 % and 8×8-pixel block means within 2 % (relative L1), with
//! fogbank at 2·10⁶ samples per image or more for the noisiest scenes. And
//! the reader's refusals name file, line, tag and plugin.

use fogbank_render::{render, Progress, RenderOptions};
use fogbank_scene::load_scene;

use crate::support::mitsuba_agreement;
use mitsuba_agreement::{assert_agrees, scenes, spp_for};

fn agree(name: &str) {
    agree_with(name, &[]);
}

/// [`agree`] with `--set` overrides.
fn agree_with(name: &str, overrides: &[String]) {
    let spp = spp_for(name);
    let scene = load_scene(Some(&scenes().join(format!("{name}.xml"))), overrides).unwrap();
    let opts = RenderOptions::new(spp, 7);
    assert_agrees(name, &render(&scene, &opts, &Progress::default()).film);
}

#[test]
fn null_bounded_mesh_medium_agrees_with_mitsuba() {
    agree("null_mesh_medium");
}

#[test]
fn medium_behind_a_thin_dielectric_with_an_area_light_agrees_with_mitsuba() {
    agree("thin_area");
}

#[test]
fn light_inside_a_medium_agrees_with_mitsuba() {
    agree("light_in_medium");
}

#[test]
fn media_inside_smooth_and_rough_dielectrics_agree_with_mitsuba() {
    agree("dielectric_media");
}

#[test]
fn ground_under_a_cloud_in_sun_and_sky_agrees_with_mitsuba() {
    agree("cloud_ground");
}

#[test]
fn surfaces_under_an_environment_map_and_an_area_light_agree_with_mitsuba() {
    agree("surfaces_env_area");
}

#[test]
fn fog_among_many_small_emitters_agrees_with_mitsuba() {
    agree("fog_emitters");
}

/// The same 300 emitters picked through the light BVH: NEE by importance
/// at the point, MIS weights with the pmf re-derived along each light's
/// trail.
#[test]
fn fog_among_many_small_emitters_through_a_light_bvh_agrees_with_mitsuba() {
    agree_with("fog_emitters", &["render.light_sampler=bvh".into()]);
}

#[test]
fn chromatic_homogeneous_and_gridded_media_agree_with_mitsuba() {
    agree("chromatic");
}

#[test]
fn spot_light_in_fog_agrees_with_mitsuba() {
    agree("spot_fog");
}

/// Analytic `sphere`s and `disk`s: intersected exactly, Mitsuba's normals
/// and UVs (checkerboards in both parameterisations), a medium bounded by a
/// null sphere, an emitting sphere sampled by its cone and an emitting
/// elliptical disk.
#[test]
fn analytic_spheres_and_disks_agree_with_mitsuba() {
    agree("analytic_shapes");
}

/// `shapegroup`s placed by `instance`s (a top-level BVH over the
/// instances; turned, stretched, mirrored; meshes and analytic spheres).
#[test]
fn instanced_shape_groups_agree_with_mitsuba() {
    agree("instances");
}

#[test]
fn bitmap_textures_agree_with_mitsuba() {
    agree("bitmap_textures");
}

// Scenes written the way Mitsuba's users write them (users_*.xml): shared
// `include/` files (nested, or found through a `<path>`), meshes beside the
// top file, sensors at their defaults (50 mm focal length, clip planes),
// Beckmann microfacets at their defaults and with `sample_visible = false`,
// and spectra (wavelength:value pairs and constants) on emitters,
// reflectances, conductors and media.

/// Beckmann roughconductor at every default, Beckmann with spectral η and
/// k, GGX sampling normals from D cos θ.
#[test]
fn default_beckmann_conductors_agree_with_mitsuba() {
    agree("users_beckmann_conductor");
}

/// A Beckmann roughdielectric at its defaults around a medium with a
/// spectral albedo, a Beckmann pane without visible-normal sampling, a
/// 35 mm lens.
#[test]
fn default_beckmann_dielectrics_agree_with_mitsuba() {
    agree("users_beckmann_dielectric");
}

/// Beckmann roughplastics (spectral base, D cos θ sampling with the
/// nonlinear model, a checkerboard).
#[test]
fn default_beckmann_plastics_agree_with_mitsuba() {
    agree("users_beckmann_plastic");
}

/// A camera inside fog with near and far clip planes, a portrait film with
/// the fov along its smaller axis.
#[test]
fn clip_planes_in_fog_agree_with_mitsuba() {
    agree("users_clip_fog");
}

/// Directional, spot, area and constant emitters, a medium's σ_t and
/// albedo and reflectances given as spectra.
#[test]
fn spectral_emitters_and_media_agree_with_mitsuba() {
    agree("users_spectral_lights");
}

/// The studio found through a `<path>` folder; a mesh named from the top
/// file.
#[test]
fn includes_through_path_folders_agree_with_mitsuba() {
    agree("users_path_include");
}

fn refusal(xml: &str) -> String {
    let dir = std::env::temp_dir().join(format!("fogbank-xml-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("t{}.xml", xml.len()));
    std::fs::write(&path, xml).unwrap();
    let Err(e) = load_scene(Some(&path), &[]) else {
        panic!("{} was accepted", path.display());
    };
    let e = e.0;
    assert!(e.contains(&path.display().to_string()), "{e}");
    e
}

#[test]
fn unsupported_plugins_and_parameters_are_refused_by_name_and_line() {
    let head = "<scene version=\"3.0.0\">\n";
    let e = refusal(&format!(
        "{head}<shape type=\"cube\">\n<bsdf type=\"roughplastic\"><float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>\n</shape>\n</scene>"
    ));
    assert!(
        e.contains(":3:") && e.contains("roughplastic") && e.contains("anisotropic"),
        "{e}"
    );
    let e = refusal(&format!(
        "{head}<shape type=\"cube\">\n<bsdf type=\"diffuse\">\n<float name=\"roughness\" value=\"1\"/>\n</bsdf>\n</shape>\n</scene>"
    ));
    assert!(
        e.contains(":4:") && e.contains("roughness") && e.contains("diffuse"),
        "{e}"
    );
    let e = refusal(&format!("{head}<shape type=\"cube\"/>\n<bogus/>\n</scene>"));
    assert!(e.contains(":3:") && e.contains("<bogus"), "{e}");
    let e = refusal(&format!("{head}<shape type=\"cube\"\n</scene>"));
    assert!(e.contains("not well-formed"), "{e}");
    let e = refusal(&format!(
        "{head}<default name=\"r\" value=\"0.5\"/>\n<shape type=\"cube\"><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"$r, $g, 1\"/></bsdf></shape>\n</scene>"
    ));
    assert!(e.contains("$g"), "{e}");
    let e = refusal(&format!(
        "{head}<emitter type=\"spot\">\n<float name=\"beam_width\" value=\"30\"/>\n</emitter>\n</scene>"
    ));
    assert!(
        e.contains(":2:") && e.contains("beam_width ≤ cutoff_angle"),
        "{e}"
    );
    let e = refusal(&format!(
        "{head}<shape type=\"cube\">\n<bsdf type=\"diffuse\">\n<texture type=\"bitmap\" name=\"reflectance\">\n<string name=\"filename\" value=\"no_such.png\"/>\n</texture>\n</bsdf>\n</shape>\n</scene>"
    ));
    assert!(e.contains(":4:") && e.contains("no_such.png"), "{e}");
    let e = refusal(&format!(
        "{head}<shape type=\"cube\">\n<bsdf type=\"diffuse\">\n<texture type=\"bitmap\" name=\"reflectance\">\n<string name=\"filename\" value=\"{}\"/>\n<string name=\"format\" value=\"fp16\"/>\n</texture>\n</bsdf>\n</shape>\n</scene>",
        scenes().join("textures/tiles_24x16.png").display()
    ));
    assert!(e.contains("format `fp16`"), "{e}");
    let e = refusal(&format!("{head}<integrator type=\"ptracer\"/>\n</scene>"));
    assert!(e.contains("integrator `ptracer`"), "{e}");
    let e = refusal(&format!(
        "{head}<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><film type=\"hdrfilm\"/></sensor>\n</scene>"
    ));
    assert!(e.contains("gaussian"), "{e}");
    let e = refusal(&format!(
        "{head}<include filename=\"missing.xml\"/>\n</scene>"
    ));
    assert!(e.contains("missing.xml"), "{e}");
}

#[test]
fn defaults_substitution_includes_and_refs() {
    let dir = std::env::temp_dir().join(format!("fogbank-xml-inc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("materials.xml"),
        "<scene version=\"3.0.0\"><bsdf type=\"diffuse\" id=\"grey\"><rgb name=\"reflectance\" value=\"$albedo\"/></bsdf></scene>",
    )
    .unwrap();
    let main = dir.join("main.xml");
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\">\n<default name=\"albedo\" value=\"0.25\"/>\n<include filename=\"materials.xml\"/>\n\
         <integrator type=\"moment\"><integrator type=\"volpath\"><integer name=\"max_depth\" value=\"3\"/></integrator></integrator>\n\
         <sensor type=\"perspective\"><float name=\"fov\" value=\"30\"/><transform name=\"to_world\"><lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>\n\
         <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"6\"/><rfilter type=\"box\"/></film></sensor>\n\
         <shape type=\"rectangle\"><ref id=\"grey\"/></shape>\n\
         <emitter type=\"directional\"><vector name=\"direction\" value=\"0, 0, -1\"/><rgb name=\"irradiance\" value=\"1\"/></emitter>\n</scene>",
    )
    .unwrap();
    let scene = load_scene(Some(&main), &[]).unwrap();
    let film = render(&scene, &RenderOptions::new(1, 0), &Progress::default()).film;
    // The rectangle fills the centre: 0.25/π · 1 (the camera's +z looks at
    // its front).
    let c = film.mean()[3 * 8 + 4][0];
    assert!((c - 0.25 / std::f32::consts::PI).abs() < 1e-5, "{c}");
    assert_eq!(scene.camera.width, 8);
}

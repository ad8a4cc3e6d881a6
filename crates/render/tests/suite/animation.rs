//! `[animation]`: keyframe interpolation, per-frame file names and the
//! errors for bad keys or missing frames.

use fogbank_render::animation::frame_path;
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

const BASE: &str = include_str!("../scenes/animation_base.toml");

fn frame(text: &str, f: u32) -> Result<Scene, String> {
    parse_scene(text, "test", &[])
        .and_then(|d| Scene::build_frame(d, Path::new("."), f))
        .map_err(|e| e.0)
}

#[test]
fn keys_interpolate_linearly_and_hold_outside() {
    let s = frame(BASE, 5).unwrap();
    assert!((s.camera.origin.x - 0.5).abs() < 1e-6);
    let b = s.media[0].medium.world_bounds();
    let b0 = frame(BASE, 0).unwrap().media[0].medium.world_bounds();
    assert!(((b.min.y - b0.min.y) - 0.25).abs() < 1e-5);
    // One key: held at every frame.
    for f in [0, 5, 10] {
        let s = frame(BASE, f).unwrap();
        match &s.lights[0] {
            fogbank_render::lights::Light::Point { position, .. } => {
                assert_eq!(position.to_array(), [0.0, 1.0, 0.0])
            }
            _ => unreachable!(),
        }
    }
}

#[test]
fn frame_paths_substitute_the_frame_number() {
    assert_eq!(frame_path("plume_{frame:04}.vdb", 42), "plume_0042.vdb");
    assert_eq!(frame_path("a{frame}b", 7), "a7b");
    assert_eq!(frame_path("still.vdb", 7), "still.vdb");
}

#[test]
fn bad_animation_keys_are_named() {
    for (from, to, expect) in [
        (
            "frame = 10\nfrom",
            "frame = 12\nfrom",
            "animation.camera.1.frame: 12 is outside 0..=10",
        ),
        (
            "light = 0\nframe = 5",
            "light = 3\nframe = 5",
            "animation.lights.0.light: 3 is not a light index",
        ),
        (
            "position = [0.0, 1.0, 0.0]",
            "rotate = [0.0, 1.0, 0.0, 3.0]",
            "animation.lights.0.rotate: light 0 is a point light",
        ),
        (
            "frames = 11",
            "frames = 0",
            "animation.frames: 0 is outside",
        ),
        (
            "medium = 0\nframe = 10",
            "medium = 0\nframe = 0",
            "keys must be in increasing frame order",
        ),
    ] {
        let text = BASE.replacen(from, to, 1);
        let e = frame(&text, 0)
            .err()
            .unwrap_or_else(|| panic!("{to} accepted"));
        assert!(e.contains(expect), "{to}: {e}");
    }
    let e = frame(BASE, 11).err().unwrap();
    assert!(
        e.contains("frame 11: the animation has frames 0..=10"),
        "{e}"
    );
    let still = BASE.split("[animation]").next().unwrap();
    let e = frame(still, 1).err().unwrap();
    assert!(e.contains("no [animation]"), "{e}");
}

#[test]
fn a_missing_frame_file_names_the_frame_and_file() {
    let dir = std::env::temp_dir().join(format!("fogbank_anim_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let raw = |f: u32| dir.join(format!("d_{f:02}.raw"));
    std::fs::write(raw(0), vec![0u8; 8]).unwrap();
    let text = format!(
        "[camera]\nwidth = 4\nheight = 4\n[[media]]\ndensity = {{ raw = \"{}\", dims = [2, 2, 2], type = \"u8\" }}\n[animation]\nframes = 3\n",
        dir.join("d_{frame:02}.raw").display()
    );
    assert!(frame(&text, 0).is_ok());
    let e = frame(&text, 1).err().unwrap();
    assert!(e.starts_with("frame 1: ") && e.contains("d_01.raw"), "{e}");
}

const PLUME: &str = include_str!("../scenes/animation_plume.toml");

#[test]
fn a_plume_advances_in_time_and_moves_with_its_velocity() {
    let (s0, s2) = (frame(PLUME, 0).unwrap(), frame(PLUME, 2).unwrap());
    assert_eq!(s2.frame_dt, 1.0 / 8.0);
    assert!(
        s2.media[0].source.contains("at 0.25 s"),
        "{}",
        s2.media[0].source
    );
    assert!(
        s0.media[0].source.contains("at 0 s"),
        "{}",
        s0.media[0].source
    );
    // The unit box [−½, ½]³: the plume rises 0.15 box heights per second
    // and swirls at 0.8 rad/s about the vertical axis through the centre.
    let v = s2.media[0]
        .velocity
        .as_ref()
        .expect("a plume has a velocity");
    let at = v.at(fogbank_math::Vec3::new(0.1, 0.0, 0.0));
    assert!(
        (at - fogbank_math::Vec3::new(0.0, 0.15, -0.08)).length() < 1e-5,
        "{at}"
    );
    assert_eq!(
        v.at(fogbank_math::Vec3::new(0.0, 2.0, 0.0)),
        fogbank_math::Vec3::ZERO
    );
    // A still scene has no frame time; a constant velocity is taken as given.
    let still = PLUME.split("[animation]").next().unwrap().replace(
        "seed = 3 }",
        "seed = 3 }\nvelocity = { constant = [1.0, 2.0, 3.0] }",
    );
    let s = frame(&still, 0).unwrap();
    assert_eq!(s.frame_dt, 0.0);
    let v = s.media[0].velocity.as_ref().unwrap();
    assert_eq!(v.at(fogbank_math::Vec3::ZERO).to_array(), [1.0, 2.0, 3.0]);
}

#[test]
fn bad_velocities_are_named() {
    let vdb =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../volume/tests/fixtures/vdb/fog_f32_zip.vdb");
    for (velocity, density, expect) in [
        (
            "{ constant = [1.0, 0.0, 0.0], procedural = \"plume\" }",
            "procedural = \"plume\"",
            "media.0.velocity: give exactly one of",
        ),
        (
            "{ procedural = \"plume\" }",
            "procedural = \"cloud\"",
            "media.0.velocity.procedural: \"plume\" needs density",
        ),
        (
            "{ procedural = \"wind\" }",
            "procedural = \"plume\"",
            "`wind` is not a procedural velocity",
        ),
        (
            "{ constant = [1.0, 0.0, 0.0], grid = \"vel\" }",
            "procedural = \"plume\"",
            "media.0.velocity.grid: only used with `vdb`",
        ),
        (
            &format!("{{ vdb = \"{}\" }}", vdb.display()),
            "procedural = \"plume\"",
            "fog_f32_zip.vdb",
        ),
        (
            &format!("{{ vdb = \"{}\", grid = \"density\" }}", vdb.display()),
            "procedural = \"plume\"",
            "density",
        ),
    ] {
        let text = format!(
            "[[media]]\ndensity = {{ {density}, resolution = 8 }}\nvelocity = {velocity}\n"
        );
        let e = frame(&text, 0)
            .err()
            .unwrap_or_else(|| panic!("{velocity} accepted"));
        assert!(e.contains(expect), "{velocity}: {e}");
    }
    let e = frame(
        "[[media]]\ndensity = { procedural = \"cloud\", resolution = 8, time = 1.0 }\n",
        0,
    )
    .err()
    .unwrap();
    assert!(
        e.contains("media.0.density.time: only used with procedural = \"plume\""),
        "{e}"
    );
}

#[test]
fn a_vdb_velocity_grid_loads_per_frame() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../volume/tests/fixtures/vdb");
    let text = format!(
        "[[media]]\ndensity = {{ vdb = \"{0}/density_vel.vdb\", grid = \"density\" }}\nvelocity = {{ vdb = \"{0}/density_vel.vdb\", grid = \"vel\" }}\n",
        dir.display()
    );
    let s = frame(&text, 0).unwrap();
    let v = s.media[0].velocity.as_ref().unwrap();
    let b = s.media[0].medium.world_bounds();
    let (mut moving, mut n) = (0, 0);
    for i in 0..512 {
        let f =
            fogbank_math::Vec3::new((i % 8) as f32, ((i / 8) % 8) as f32, (i / 64) as f32) / 7.0;
        let at = v.at(b.min + (b.max - b.min) * f);
        assert!(at.is_finite());
        moving += (at.length() > 0.0) as u32;
        n += 1;
    }
    assert!(moving > 0, "no motion at {n} points");
}

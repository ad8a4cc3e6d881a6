//! A NanoVDB file renders exactly as the OpenVDB file it was converted
//! from: the `nvdb` scene key yields the same grid, so the same image bit
//! for bit, and the same velocities. The committed fixtures need no tools;
//! the dragon and the sphere of `data/` are converted with `nanovdb_convert`
//! when it is installed (skipped with a message otherwise, unless
//! `FOGBANK_REQUIRE_NANOVDB=1`).

use crate::support::same_image;

use fogbank_math::testdata::tool_on_path;
use fogbank_math::{sample_data, Vec3};
use fogbank_render::{parse_scene, Scene};
use same_image::{assert_same_image, transmittance_image};
use std::path::{Path, PathBuf};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../volume/tests/fixtures")
}

/// The transmittance image (16×16, 4 spp, a fixed seed) of a scene whose
/// medium's density is `density`, seen from `from` looking at `to`.
fn image(density: &str, from: [f32; 3], to: [f32; 3]) -> Vec<[f32; 3]> {
    let text = format!(
        "[camera]\nfrom = {from:?}\nto = {to:?}\nfov = 40.0\nwidth = 16\nheight = 16\n\
         [[media]]\ndensity = {density}\nsigma_t_scale = 8.0\n\
         [integrator]\ntype = \"transmittance\"\nestimator = \"ratio_tracking\"\n"
    );
    transmittance_image(parse_scene(&text, "test", &[]).unwrap())
}

#[test]
fn nvdb_fixture_renders_as_its_vdb_source() {
    let d = fixtures();
    let (from, to) = ([20.0, 6.0, 45.0], [20.0, 5.0, 7.0]);
    let vdb = image(
        &format!("{{ vdb = \"{}/vdb/fog_f32_zip.vdb\" }}", d.display()),
        from,
        to,
    );
    for nvdb in ["fog_zip.nvdb", "fog_blosc.nvdb"] {
        let nv = image(
            &format!("{{ nvdb = \"{}/nanovdb/{nvdb}\" }}", d.display()),
            from,
            to,
        );
        assert_same_image(&nv, &vdb, nvdb);
    }
}

/// The dragon (a fog volume) and the sphere (a level set, rendered as fog)
/// converted to float NanoVDB grids render bit for bit as the `.vdb` files.
#[test]
fn converted_real_files_render_as_their_vdb_files() {
    let Some(tool) = nanovdb_convert() else {
        return;
    };
    for (file, from, to) in [
        ("dragon.vdb", [3.0, 4.5, 13.0], [5.0, 2.5, 5.0]),
        ("sphere.vdb", [0.0, 1.0, 9.0], [0.0, 0.0, 0.0]),
    ] {
        let vdb = sample_data::committed(file);
        let out = std::env::temp_dir().join(format!("fogbank-{file}-{}.nvdb", std::process::id()));
        let status = std::process::Command::new(&tool)
            .arg("-f")
            .arg(&vdb)
            .arg(&out)
            .output()
            .unwrap();
        assert!(status.status.success(), "nanovdb_convert {}", vdb.display());
        let v = image(&format!("{{ vdb = \"{}\" }}", vdb.display()), from, to);
        let nv = image(&format!("{{ nvdb = \"{}\" }}", out.display()), from, to);
        let _ = std::fs::remove_file(&out);
        assert_same_image(&nv, &v, file);
    }
}

#[test]
fn nvdb_is_one_of_the_exclusive_sources() {
    let d = fixtures();
    let text = format!(
        "[[media]]\ndensity = {{ vdb = \"{0}/vdb/fog_f32_zip.vdb\", nvdb = \"{0}/nanovdb/fog_zip.nvdb\" }}\n",
        d.display()
    );
    let desc = parse_scene(&text, "test", &[]).unwrap();
    let e = Scene::build(desc, Path::new(".")).err().unwrap().0;
    assert!(e.contains("give exactly one of `vdb`, `nvdb`"), "{e}");
    let text = format!(
        "[[media]]\ndensity = {{ nvdb = \"{}/nanovdb/fog_zip.nvdb\", grid = \"smoke\" }}\n",
        d.display()
    );
    let desc = parse_scene(&text, "test", &[]).unwrap();
    let e = Scene::build(desc, Path::new(".")).err().unwrap().0;
    assert!(e.contains("fog_zip.nvdb") && e.contains("smoke"), "{e}");
}

fn nanovdb_convert() -> Option<PathBuf> {
    tool_on_path(
        "nanovdb_convert",
        "FOGBANK_REQUIRE_NANOVDB",
        "Debian: apt-get install libnanovdb-tools",
    )
}

#[test]
fn nvdb_velocity_is_the_vdb_velocity() {
    let d = fixtures();
    let scene = |key: &str, file: &str| {
        let text = format!(
            "[[media]]\ndensity = {{ vdb = \"{0}/vdb/density_vel.vdb\", grid = \"density\" }}\n\
             velocity = {{ {key} = \"{0}/{file}\", grid = \"vel\" }}\n",
            d.display()
        );
        let desc = parse_scene(&text, "test", &[]).unwrap();
        Scene::build_frame(desc, Path::new("."), 0).unwrap()
    };
    let (a, b) = (
        scene("vdb", "vdb/density_vel.vdb"),
        scene("nvdb", "nanovdb/density_vel_zip.nvdb"),
    );
    let (va, vb) = (
        a.media[0].velocity.as_ref().unwrap(),
        b.media[0].velocity.as_ref().unwrap(),
    );
    let bounds = a.media[0].medium.world_bounds();
    let mut moving = 0;
    for i in 0..512 {
        let f = Vec3::new((i % 8) as f32, ((i / 8) % 8) as f32, (i / 64) as f32) / 7.0;
        let p = bounds.min + (bounds.max - bounds.min) * f;
        assert_eq!(va.at(p), vb.at(p), "at {p}");
        moving += (va.at(p).length() > 0.0) as u32;
    }
    assert!(moving > 0);
}

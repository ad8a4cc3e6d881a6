//! `fogbank convert`: a scene converted to TOML renders bit for bit as its
//! pbrt-v4 or Mitsuba source (the same description results); a TOML scene
//! written as Mitsuba XML and read back renders the same image in
//! expectation (a per-pixel z-test: the camera frame and the grids'
//! placement round through text and `lookat`, so the images differ in the
//! last bits, not in their means); volumes keep every active voxel.

use fogbank_image::metrics::ztest::ztest;
use fogbank_math::{sample_data, testdata::external_data};
use fogbank_render::overrides::apply_override;
use fogbank_render::render::{render, Progress, RenderOptions};
use fogbank_render::world::field::{field_data, FieldDesc};
use fogbank_render::{parse_scene, Film, Scene, SceneDesc};
use fogbank_scene::convert::{convert, ConvertOptions};
use fogbank_scene::read_scene_source;
use fogbank_volume::loaders::{nanovdb, vdb};
use fogbank_volume::writers::Codec;
use fogbank_volume::{DensityData, Precision};
use glam::{DAffine3, DMat4, DVec3};
use std::path::{Path, PathBuf};

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// A fresh folder for test `name` (tests run at once), removed when the
/// test ends.
struct OutDir(PathBuf);

impl std::ops::Deref for OutDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        std::fs::remove_dir_all(&self.0).ok();
    }
}

fn out_dir(name: &str) -> OutDir {
    let d = std::env::temp_dir().join(format!("fogbank-convert-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    OutDir(d)
}

fn load(path: &Path) -> (SceneDesc, PathBuf) {
    let src = read_scene_source(path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let desc = parse_scene(&src.text, &src.origin, &[]).unwrap_or_else(|e| panic!("{e}"));
    (desc, src.base)
}

fn film(path: &Path, spp: u32) -> Film {
    let (desc, base) = load(path);
    let scene = Scene::build(desc, &base).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    render(&scene, &RenderOptions::new(spp, 3), &Progress::default()).film
}

fn convert_ok(input: &Path, output: &Path) -> Vec<String> {
    convert(input, output, &ConvertOptions::default())
        .unwrap_or_else(|e| panic!("{} → {}: {e}", input.display(), output.display()))
        .notes
}

/// `source` converted to TOML in another folder parses to the same
/// description and renders bit for bit as the source.
fn assert_toml_renders_identically(source: &Path, name: &str) {
    let dir = out_dir(name);
    let out = dir.join(format!("{name}.toml"));
    assert!(convert_ok(source, &out).is_empty());
    assert_eq!(
        load(source).0,
        load(&out).0,
        "{name}: the descriptions differ"
    );
    let (a, b) = (film(source, 4).mean(), film(&out, 4).mean());
    assert!(
        a.iter().flatten().any(|&v| v > 0.0),
        "{name}: a black image"
    );
    let bits =
        |img: &[[f32; 3]]| -> Vec<u32> { img.iter().flatten().map(|v| v.to_bits()).collect() };
    assert!(bits(&a) == bits(&b), "{name}: the images differ");
}

#[test]
fn pbrt_to_toml_renders_bit_identically() {
    assert_toml_renders_identically(&repo("crates/scene/tests/pbrt/offcentre.pbrt"), "offcentre");
    assert_toml_renders_identically(
        &repo("crates/scene/tests/pbrt/fog_sphere.pbrt"),
        "fog_sphere",
    );
}

/// A pbrt `uniformgrid` medium (an array in the reading process's memory).
const UNIFORM_GRID: &str = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 25\n\
    Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\nAttributeBegin\n\
    Translate 0 0 -1\nMakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \
    \"integer ny\" 1 \"integer nz\" 1 \"float density\" [0.25 1] \"point3 p0\" [-1 -1 -1] \
    \"point3 p1\" [1 1 1] \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [0 0 0] \"float scale\" 3\n\
    AttributeEnd\nAttributeBegin\nMediumInterface \"g\" \"\"\nMaterial \"interface\"\n\
    Shape \"sphere\"\nAttributeEnd\nLightSource \"infinite\"\n";

#[test]
fn a_pbrt_uniform_grid_is_written_as_a_vol_beside_the_toml() {
    let dir = out_dir("uniformgrid");
    let src = dir.join("grid.pbrt");
    std::fs::write(&src, UNIFORM_GRID).unwrap();
    let out_folder = out_dir("uniformgrid-out");
    let out = out_folder.join("grid.toml");
    convert_ok(&src, &out);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        !text.contains("array:") && text.contains("vol = \"grid_array0.vol\""),
        "{text}"
    );
    assert!(out.with_file_name("grid_array0.vol").is_file());
    let (a, b) = (film(&src, 64), film(&out, 64));
    let z = ztest(&a.mean_image(), &b.mean_image()).unwrap();
    assert!(
        z.pass,
        "{} pixels fail (max |z| {:.2})",
        z.failing_pixels, z.max_abs_z
    );
    let bits = |f: &Film| -> Vec<u32> { f.mean().iter().flatten().map(|v| v.to_bits()).collect() };
    assert!(bits(&a) == bits(&b), "the images differ");
}

#[test]
fn mitsuba_to_toml_renders_bit_identically() {
    for name in ["cloud_ground", "analytic_shapes", "chromatic"] {
        assert_toml_renders_identically(&repo(&format!("scenes/mitsuba/{name}.xml")), name);
    }
}

#[test]
fn toml_in_its_own_folder_keeps_relative_names_and_elsewhere_makes_them_absolute() {
    let dir = out_dir("relative");
    let dragon = sample_data::committed("dragon.vdb");
    std::fs::copy(&dragon, dir.join("dragon.vdb")).unwrap();
    let src = dir.join("scene.toml");
    std::fs::write(&src, "[[media]]\ndensity = { vdb = \"dragon.vdb\" }\n").unwrap();
    convert_ok(&src, &dir.join("same.toml"));
    let same = std::fs::read_to_string(dir.join("same.toml")).unwrap();
    assert!(same.contains("vdb = \"dragon.vdb\""), "{same}");
    let elsewhere = out_dir("relative-elsewhere");
    let other = elsewhere.join("moved.toml");
    convert_ok(&src, &other);
    let moved = std::fs::read_to_string(&other).unwrap();
    assert!(!moved.contains("vdb = \"dragon.vdb\""), "{moved}");
    Scene::build(load(&other).0, other.parent().unwrap()).unwrap();
    // A scene in a subfolder written to the files' folder names them
    // relative to it.
    let sub = dir.join("sub");
    std::fs::create_dir_all(&sub).unwrap();
    let deep = sub.join("deep.toml");
    std::fs::write(&deep, "[[media]]\ndensity = { vdb = \"../dragon.vdb\" }\n").unwrap();
    convert_ok(&deep, &dir.join("up.toml"));
    let up = std::fs::read_to_string(dir.join("up.toml")).unwrap();
    assert!(up.contains("vdb = \"dragon.vdb\""), "{up}");
    Scene::build(load(&dir.join("up.toml")).0, &dir).unwrap();
}

/// The renders of `a` and `b` (`spp` samples) pass the per-pixel z-test.
fn assert_same_in_expectation(a: &Path, b: &Path, spp: u32) {
    let (fa, fb) = (film(a, spp), film(b, spp));
    let z = ztest(&fa.mean_image(), &fb.mean_image()).unwrap();
    assert!(
        z.pass,
        "{} vs {}: {} pixels fail (max |z| {:.2} at {:?}, threshold {:.2})",
        a.display(),
        b.display(),
        z.failing_pixels,
        z.max_abs_z,
        z.max_abs_z_pixel,
        z.threshold
    );
    assert!(fa.mean().iter().flatten().any(|&v| v > 0.0));
}

const FOGGY_TOML: &str = r#"
[camera]
from = [6.0, 4.0, 14.0]
to = [6.0, 2.5, 4.5]
fov = 40.0
width = 24
height = 16

[[media]]
density = { vdb = "DRAGON" }
sigma_t_scale = 4.0
albedo = [0.9, 0.8, 0.7]
phase = { type = "hg", g = 0.4 }
to_world = { translate = [0.25, -0.5, 0.125], rotate = [0.0, 1.0, 0.0, 10.0] }
filter = "trilinear"
precision = "f32"

[[media]]
density = { procedural = "constant", resolution = 2, value = 0.5 }
sigma_t_scale = 1.0
to_world = { translate = [3.0, 0.5, 9.0], scale = 2.0 }

[[lights]]
type = "point"
position = [6.0, 12.0, 10.0]
intensity = [200.0, 200.0, 200.0]

[[lights]]
type = "constant"
radiance = [0.2, 0.2, 0.3]

[[shapes]]
type = "rectangle"
to_world = { translate = [6.0, -1.0, 4.0], rotate = [1.0, 0.0, 0.0, -90.0], scale = 10.0 }
bsdf = { type = "roughplastic", alpha = 0.3, diffuse_reflectance = [0.5, 0.6, 0.4] }

[[shapes]]
type = "sphere"
to_world = { translate = [2.0, 1.0, 5.0] }
bsdf = { type = "diffuse", reflectance = { type = "checkerboard", to_uv = { scale = [4.0, 4.0] } } }

[integrator]
type = "volpath"
max_depth = 6

[render]
spp = 16
"#;

#[test]
fn toml_to_mitsuba_and_back_renders_the_same_in_expectation() {
    let dir = out_dir("to-mitsuba");
    let src = dir.join("foggy.toml");
    let dragon = sample_data::committed("dragon.vdb");
    std::fs::write(
        &src,
        FOGGY_TOML.replace("DRAGON", &dragon.display().to_string()),
    )
    .unwrap();
    let xml = dir.join("foggy.xml");
    let notes = convert_ok(&src, &xml);
    assert!(notes.iter().any(|n| n.contains("near_clip")), "{notes:?}");
    assert!(dir.join("foggy_medium0.vol").is_file());
    let (back, _) = load(&xml);
    assert_eq!((back.media.len(), back.lights.len()), (2, 2));
    // The two media's bounding cubes are the extra shapes.
    assert_eq!(back.shapes.len(), 4);
    assert_same_in_expectation(&src, &xml, 256);
}

#[test]
fn a_mirrored_camera_round_trips_through_mitsuba() {
    let dir = out_dir("mirror");
    let src = repo("crates/scene/tests/pbrt/fog_sphere.pbrt");
    let xml = dir.join("fog_sphere.xml");
    convert_ok(&src, &xml);
    let (back, _) = load(&xml);
    assert!(back.camera.mirror);
    assert_same_in_expectation(&src, &xml, 256);
}

#[test]
fn mitsuba_scenes_written_again_render_the_same_in_expectation() {
    let dir = out_dir("again");
    // A grid medium in a null cube; chromatic homogeneous media.
    for name in ["cloud_ground", "chromatic"] {
        let src = repo(&format!("scenes/mitsuba/{name}.xml"));
        let again = dir.join(format!("{name}.xml"));
        convert_ok(&src, &again);
        assert_same_in_expectation(&src, &again, 64);
    }
}

#[test]
fn what_mitsuba_cannot_express_is_refused_naming_it() {
    let dir = out_dir("refused");
    let o = ConvertOptions::default();
    let tr = dir.join("tr.toml");
    std::fs::write(&tr, "[integrator]\ntype = \"transmittance\"\n").unwrap();
    let e = convert(&tr, &dir.join("tr.xml"), &o).unwrap_err();
    assert!(e.0.contains("transmittance"), "{e}");
    let rgb = dir.join("rgb.toml");
    let dragon = sample_data::committed("dragon.vdb");
    let text = format!(
        "[[media]]\ndensity = {{ vdb = \"{}\" }}\nsigma_t_scale = [1.0, 2.0, 3.0]\n\
         [integrator]\ntype = \"volpath\"\n",
        dragon.display()
    );
    std::fs::write(&rgb, text).unwrap();
    let e = convert(&rgb, &dir.join("rgb.xml"), &o).unwrap_err();
    assert!(e.0.contains("media.0.sigma_t_scale"), "{e}");
}

/// The built-in scene (a procedural cumulus under the gradient sky and a
/// sun), made small: 24×16 pixels, a 32³ cloud of f32 voxels, σ_t scale 10,
/// `volpath` to depth 8 with its default estimator.
fn sky_toml() -> String {
    let mut doc: toml::Table = toml::from_str(fogbank_render::scene::DEFAULT_SCENE).unwrap();
    let set: [(&str, toml::Value); 6] = [
        ("camera.width", 24.into()),
        ("camera.height", 16.into()),
        ("media.0.density.resolution", 32.into()),
        ("media.0.precision", "f32".into()),
        ("media.0.sigma_t_scale", 10.0.into()),
        ("integrator.max_depth", 8.into()),
    ];
    for (path, value) in set {
        apply_override(&mut doc, path, value).unwrap();
    }
    doc["integrator"]
        .as_table_mut()
        .unwrap()
        .remove("estimator");
    doc.remove("render");
    toml::to_string(&doc).unwrap()
}

#[test]
fn a_sky_is_baked_into_an_envmap_and_a_procedural_cloud_voxelised() {
    let dir = out_dir("sky");
    let src = dir.join("sky.toml");
    std::fs::write(&src, sky_toml()).unwrap();
    let xml = dir.join("sky.xml");
    let notes = convert_ok(&src, &xml);
    assert!(notes.iter().any(|n| n.contains("lights.0")), "{notes:?}");
    assert!(dir.join("sky_light0.exr").is_file() && dir.join("sky_medium0.vol").is_file());
    assert_same_in_expectation(&src, &xml, 256);
}

/// Every leaf (origin, values, active mask) and tile of two grids agree.
fn assert_same_voxels(a: &vdb::VdbGrid, b: &vdb::VdbGrid, what: &str) {
    assert_eq!(a.active_voxel_count(), b.active_voxel_count(), "{what}");
    assert_eq!(a.leaves, b.leaves, "{what}: leaves differ");
    assert_eq!(a.tiles, b.tiles, "{what}: tiles differ");
    assert_eq!(a.index_to_world, b.index_to_world, "{what}");
}

#[test]
fn vdb_to_nvdb_to_vdb_keeps_every_active_voxel() {
    let dir = out_dir("volumes");
    let mut files = vec![sample_data::committed("dragon.vdb")];
    files.extend(
        ["cube.vdb", "sphere.vdb"]
            .into_iter()
            .filter_map(external_data),
    );
    for f in files {
        let name = f.file_stem().unwrap().to_str().unwrap().to_string();
        let original = vdb::read_grid(&f, None).unwrap();
        let (nv, back) = (
            dir.join(format!("{name}.nvdb")),
            dir.join(format!("{name}.vdb")),
        );
        let o = ConvertOptions {
            codec: Codec::Zip,
            ..Default::default()
        };
        convert(&f, &nv, &o).unwrap();
        convert(&nv, &back, &ConvertOptions::default()).unwrap();
        let mid = nanovdb::read_grid(&nv, None).unwrap();
        assert_same_voxels(&original, &mid, &format!("{name}.nvdb"));
        let again = vdb::read_grid(&back, None).unwrap();
        assert_same_voxels(&original, &again, &format!("{name} back"));
        assert!(original.active_voxel_count() > 0);
    }
}

#[test]
fn grid_picks_the_grid_of_a_multi_grid_file() {
    let dir = out_dir("multi");
    let src = repo("crates/volume/tests/fixtures/nanovdb/density_vel_zip.nvdb");
    let out = dir.join("density.vdb");
    let o = ConvertOptions {
        grid: Some("density".into()),
        ..Default::default()
    };
    convert(&src, &out, &o).unwrap();
    let want = nanovdb::read_grid(&src, Some("density")).unwrap();
    assert_same_voxels(&want, &vdb::read_grid(&out, None).unwrap(), "density");
    let o = ConvertOptions {
        grid: Some("nope".into()),
        ..Default::default()
    };
    let e = convert(&src, &dir.join("nope.vdb"), &o).unwrap_err().0;
    assert!(
        e.contains("density_vel_zip.nvdb") && e.contains("nope"),
        "{e}"
    );
}

/// Every voxel of the field `{ key = "src" }`, as fogbank reads it, sits
/// with its value at the same world position in the written grid `g`,
/// whose active voxels are the field's non-zero ones.
fn assert_grid_holds_field(key: &str, src: &Path, g: &vdb::VdbGrid) {
    let f: FieldDesc = toml::from_str(&format!("{key} = \"{}\"", src.display())).unwrap();
    let data = field_data(&f, key, Path::new("."), Precision::F32).unwrap();
    let DensityData::F32(field) = &data.data else {
        panic!("{key}: not an f32 grid")
    };
    let m = DMat4::from_cols_array_2d(&g.index_to_world).transpose();
    let to_index = DAffine3::from_mat4(m).inverse();
    let [nx, ny, nz] = field.dims();
    let mut nonzero = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let v = field.fetch(i as i32, j as i32, k as i32);
                nonzero += (v != 0.0) as u64;
                let centre = DVec3::new(i as f64, j as f64, k as f64) + 0.5;
                let q = to_index.transform_point3(data.to_world.transform_point3(centre));
                let ijk = q.round().as_ivec3().to_array();
                assert!((q - q.round()).abs().max_element() < 1e-6, "{key}: {q}");
                assert_eq!(g.value_at(ijk), v, "{key}: voxel {i} {j} {k}");
            }
        }
    }
    assert_eq!(g.active_voxel_count(), nonzero, "{key}");
    assert!(nonzero > 0, "{key}");
}

#[test]
fn vol_nifti_and_nrrd_become_grids_with_every_voxel_where_it_was() {
    let dir = out_dir("dense");
    let vol = dir.join("ramp.vol");
    let values: Vec<f32> = (0..6 * 5 * 4).map(|i| (i % 7) as f32 / 8.0).collect();
    // Box [1, 7] × [2, 7] × [0, 2]: voxels of 1 × 1 × ½.
    let bbox = [1., 2., 0., 7., 7., 2.];
    fogbank_volume::loaders::vol::write_vol(&vol, [6, 5, 4], 1, bbox, &values).unwrap();
    let sci = repo("crates/volume/tests/fixtures/sci");
    for (src, key, out) in [
        (vol, "vol", "ramp.vdb"),
        (sci.join("anatomical.nii"), "nifti", "anatomical.nvdb"),
        (sci.join("oblique_i16.nii.gz"), "nifti", "oblique.vdb"),
        (sci.join("lps_gzip.nrrd"), "nrrd", "lps.nvdb"),
    ] {
        let out = dir.join(out);
        convert(&src, &out, &ConvertOptions::default()).unwrap();
        let g = if out.extension().unwrap() == "nvdb" {
            nanovdb::read_grid(&out, None)
        } else {
            vdb::read_grid(&out, None)
        };
        assert_grid_holds_field(key, &src, &g.unwrap());
    }
}

#[test]
fn bad_input_names_the_file() {
    let dir = out_dir("bad");
    let o = ConvertOptions::default();
    let unknown = dir.join("scene.blend");
    std::fs::write(&unknown, "x").unwrap();
    let e = convert(&unknown, &dir.join("x.toml"), &o).unwrap_err().0;
    assert!(e.contains("scene.blend") && e.contains("extension"), "{e}");
    let e = convert(&dir.join("missing.toml"), &dir.join("x.toml"), &o)
        .unwrap_err()
        .0;
    assert!(e.contains("missing.toml"), "{e}");
    let src = repo("crates/scene/tests/pbrt/offcentre.pbrt");
    let unwritable = dir.join("no/such/folder/out.toml");
    let e = convert(&src, &unwritable, &o).unwrap_err().0;
    assert!(e.contains("out.toml"), "{e}");
    let e = convert(&src, &src, &o).unwrap_err().0;
    assert!(
        e.contains("offcentre.pbrt") && e.contains("overwrite"),
        "{e}"
    );
    let e = convert(&src, &dir.join("out.png"), &o).unwrap_err().0;
    assert!(e.contains("out.png"), "{e}");
    let e = convert(
        &sample_data::committed("dragon.vdb"),
        &dir.join("d.toml"),
        &o,
    )
    .unwrap_err()
    .0;
    assert!(e.contains("d.toml"), "{e}");
}

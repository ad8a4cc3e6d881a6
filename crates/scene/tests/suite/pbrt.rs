//! pbrt-v4 scenes: the grammar (Include splicing, comments, arrays, errors
//! naming file and line), transforms (column-major matrices, the
//! left-handed LookAt), and the mapping of media, lights and materials onto
//! fogbank's description, checked against hand-written TOML.

use fogbank_render::render::{render, Progress, RenderOptions};
use fogbank_render::{parse_scene, Scene, SceneDesc};
use fogbank_scene::pbrt::{load_pbrt, load_pbrt_str};
use fogbank_scene::read_scene_source;
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/pbrt")
        .join(name)
}

/// A `.pbrt` text (named `t.pbrt` in the fixtures' folder) as a description.
fn desc(text: &str) -> SceneDesc {
    let t = load_pbrt_str(text, &fixture("t.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    parse_scene(&toml::to_string(&t).unwrap(), "t.pbrt", &[]).unwrap()
}

/// The error of a `.pbrt` text.
fn error(text: &str) -> String {
    match load_pbrt_str(text, &fixture("t.pbrt")) {
        Ok(_) => panic!("should fail:\n{text}"),
        Err(e) => e.0,
    }
}

fn load(path: &Path) -> SceneDesc {
    let src = read_scene_source(path, &[]).unwrap_or_else(|e| panic!("{e}"));
    parse_scene(&src.text, &src.origin, &[]).unwrap()
}

fn image(d: SceneDesc) -> Vec<[f32; 3]> {
    let scene = Scene::build(d, Path::new(".")).unwrap();
    render(&scene, &RenderOptions::new(4, 3), &Progress::default())
        .film
        .mean()
}

const HEAD: &str = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nFilm \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n";

#[test]
fn a_pbrt_scene_and_its_hand_written_toml_render_bit_identically() {
    let p = load(&fixture("offcentre.pbrt"));
    let t = load(&fixture("offcentre.toml"));
    assert_eq!(p.camera, t.camera);
    let (a, b) = (image(p), image(t));
    assert!(a.iter().flatten().any(|&v| v > 0.0));
    let bits = |img: &[[f32; 3]]| {
        img.iter()
            .flatten()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert!(bits(&a) == bits(&b), "the images differ");
}

#[test]
fn lookat_puts_world_plus_x_on_the_left_as_pbrt_does() {
    let d = load(&fixture("offcentre.pbrt"));
    let scene = Scene::build(d.clone(), Path::new(".")).unwrap();
    let (x, _) = scene
        .world
        .camera
        .project(glam::Vec3::new(1.0, 0.0, 0.0))
        .unwrap();
    assert!(x < 16.0, "world +x at image x = {x}");
    // The rendered sphere: the left half is lit, the right half is not.
    let img = image(d);
    let half = |left: bool| -> f32 {
        (0..24 * 32)
            .filter(|i| ((i % 32) < 16) == left)
            .map(|i| img[i][0])
            .sum()
    };
    assert!(half(true) > 0.0 && half(false) == 0.0);
}

#[test]
fn a_mirroring_scale_before_lookat_gives_an_unmirrored_camera() {
    let d = desc("Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n");
    assert!(!d.camera.mirror);
    let d = desc(HEAD);
    assert!(d.camera.mirror);
    // Film 8×8: square, the fov (90 by default) on y.
    assert_eq!((d.camera.fov, d.camera.fov_axis.as_str()), (90.0, "y"));
    let tall = desc("Camera \"perspective\" \"float fov\" 30\nFilm \"rgb\" \"integer xresolution\" 10 \"integer yresolution\" 20\nWorldBegin\n");
    assert_eq!(
        (tall.camera.fov, tall.camera.fov_axis.as_str()),
        (30.0, "x")
    );
    assert_eq!((tall.camera.width, tall.camera.height), (10, 20));
}

#[test]
fn column_major_transform_and_concat_transform() {
    let d = desc(&format!(
        "{HEAD}Transform [1 0 0 0  0 1 0 0  0 0 1 0  2 3 4 1]\nConcatTransform [2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1]\nShape \"sphere\"\n"
    ));
    let m = d.shapes[0].to_world.matrix.unwrap();
    assert_eq!(m[0], [2.0, 0.0, 0.0, 2.0]);
    assert_eq!(m[1], [0.0, 2.0, 0.0, 3.0]);
    assert_eq!(m[2], [0.0, 0.0, 2.0, 4.0]);
}

#[test]
fn coordinate_systems_and_the_camera_frame() {
    let d = desc(&format!(
        "{HEAD}Translate 5 0 0\nCoordinateSystem \"a\"\nIdentity\nCoordSysTransform \"a\"\nShape \"sphere\"\nCoordSysTransform \"camera\"\nShape \"sphere\"\n"
    ));
    assert_eq!(d.shapes[0].to_world.matrix.unwrap()[0][3], 5.0);
    // The camera's frame: its origin is the eye.
    assert!((d.shapes[1].to_world.matrix.unwrap()[2][3] - 5.0).abs() < 1e-12);
}

#[test]
fn include_splices_tokens_so_a_statement_continues_after_the_file() {
    let d = load(&fixture("include_main.pbrt"));
    assert_eq!(d.media.len(), 1);
    // σ_t = scale (4) · (σ_a + σ_s) (2).
    assert_eq!(d.media[0].sigma_t_scale.max(), 8.0);
    assert_eq!(d.media[0].albedo, Some([0.75; 3]));
    assert_eq!(d.shapes[0].interior, Some(0));
    assert_eq!(d.shapes[0].exterior, None);
}

#[test]
fn errors_name_the_file_and_line() {
    let e = load_pbrt(&fixture("misspelt.pbrt")).unwrap_err().0;
    assert!(
        e.contains("misspelt_shape.pbrt:3:") && e.contains("radiuss"),
        "{e}"
    );
    let e = error(&format!("{HEAD}\n\nShap \"sphere\"\n"));
    assert!(
        e.contains("t.pbrt:7:") && e.contains("unknown statement `Shap`"),
        "{e}"
    );
    let e = error(&format!(
        "{HEAD}Shape \"sphere\" \"point radius\" [1 2 3]\n"
    ));
    assert!(
        e.contains("t.pbrt:5:") && e.contains("unknown parameter type `point`"),
        "{e}"
    );
    let e = error(&format!("{HEAD}Shape \"sphere\" \"integer radius\" 1\n"));
    assert!(
        e.contains("t.pbrt:5:") && e.contains("\"integer radius\" is not used"),
        "{e}"
    );
    let e = error(&format!("{HEAD}Shape \"torus\"\n"));
    assert!(e.contains("t.pbrt:5:") && e.contains("torus"), "{e}");
    let e = error(&format!("{HEAD}LightSource \"point\" \"rgb I\" [1 1]\n"));
    assert!(e.contains("t.pbrt:5:"), "{e}");
    let e = error(&format!("{HEAD}AttributeBegin\nShape \"sphere\"\n"));
    assert!(e.contains("t.pbrt:5:") && e.contains("AttributeEnd"), "{e}");
    let e = load_pbrt(&fixture("cycle.pbrt")).unwrap_err().0;
    assert!(
        e.contains("cycle.pbrt:2:") && e.contains("nested deeper"),
        "{e}"
    );
    let e = error(&format!(
        "{HEAD}Shape \"sphere\" \"float radius\" [1 [2]]\n"
    ));
    assert!(e.contains("t.pbrt:5:"), "{e}");
    let e = error(&format!("{HEAD}Texture \"t\" \"spectrum\" \"imagemap\"\n"));
    assert!(e.contains("Texture"), "{e}");
    let e = error(&format!("{HEAD}MakeNamedMedium \"m\" \"string type\" \"fog\"\nMediumInterface \"m\" \"\"\nShape \"sphere\"\n"));
    assert!(
        e.contains("t.pbrt:5:") && e.contains("unknown medium type \"fog\""),
        "{e}"
    );
}

#[test]
fn comments_arrays_and_bare_values() {
    let d = desc(&format!(
        "{HEAD}# a comment with \"quotes\" [ and brackets\nShape \"sphere\" \"float radius\" 2 # trailing\nShape \"sphere\" \"float radius\" [ 3 ]\n"
    ));
    assert_eq!(d.shapes[0].to_world.matrix.unwrap()[0][0], 2.0);
    assert_eq!(d.shapes[1].to_world.matrix.unwrap()[0][0], 3.0);
}

#[test]
fn homogeneous_medium_fills_its_shapes_box_or_the_scene() {
    let d = desc(&format!(
        "{HEAD}MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.1 0.2 0.3] \"rgb sigma_s\" [0.9 0.8 0.7] \"float scale\" 2 \"float g\" 0.3 \"rgb Le\" [1 2 3] \"float Lescale\" 0.5\nAttributeBegin\nMediumInterface \"fog\" \"\"\nMaterial \"interface\"\nTranslate 1 0 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
    ));
    let m = &d.media[0];
    assert_eq!(m.sigma_t_scale.max(), 2.0);
    assert_eq!(m.albedo, Some([0.9, 0.8, 0.7]));
    let e = m.emission.as_ref().unwrap();
    assert_eq!((e.color, e.scale), ([1.0, 2.0, 3.0], 0.5));
    // The constant grid spans the sphere's box: centre (1, 0, 0), edge 1.
    let t = m.to_world.matrix.unwrap();
    assert_eq!((t[0][0], t[0][3]), (1.0, 1.0));
    // As the camera's medium it is unbounded: the scene's box.
    let d = desc("LookAt 0 0 5  0 0 0  0 1 0\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMediumInterface \"fog\"\nCamera \"perspective\"\nWorldBegin\nShape \"sphere\"\n");
    let t = d.media[0].to_world.matrix.unwrap();
    assert!(
        t[2][2] > 6.0,
        "the box holds the camera and the sphere: {t:?}"
    );
    assert_eq!(d.media[0].sigma_t_scale.max(), 2.0);
}

#[test]
fn nanovdb_medium_reads_its_grids_where_the_file_has_them() {
    let file = "../../../volume/tests/fixtures/nanovdb/density_vel_zip.nvdb";
    // Before the camera, under a transform, and the camera's medium.
    let d = desc(&format!(
        "Translate 1 2 3\nMakeNamedMedium \"smoke\" \"string type\" \"nanovdb\" \"string filename\" \"{file}\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [3 3 3] \"float scale\" 0.5\nMediumInterface \"smoke\"\nIdentity\nCamera \"perspective\"\nWorldBegin\n"
    ));
    let m = &d.media[0];
    assert!(m
        .density
        .files
        .path_of("nvdb")
        .unwrap()
        .ends_with("density_vel_zip.nvdb"));
    assert_eq!(m.density.grid.as_deref(), Some("density"));
    assert_eq!(m.sigma_t_scale.max(), 2.0);
    assert_eq!(m.albedo, Some([0.75; 3]));
    // A constant sampled spectrum is grey, as in pbrt.
    let d2 = desc(&format!(
        "{HEAD}MakeNamedMedium \"s\" \"string type\" \"homogeneous\" \"spectrum sigma_a\" [300 20 830 20] \"spectrum sigma_s\" [300 160 830 160]\nMediumInterface \"s\" \"\"\nShape \"sphere\"\n"
    ));
    assert_eq!(format!("{:?}", d2.media[0].sigma_t_scale), "Grey(180.0)");
    assert_eq!(m.to_world.matrix.unwrap()[1][3], 2.0);
    // No "temperature" grid in this file: no emission, as pbrt.
    assert!(m.emission.is_none());
    let d = desc(&format!(
        "{HEAD}MakeNamedMedium \"hot\" \"string type\" \"nanovdb\" \"string filename\" \"{file}\" \"string temperaturename\" \"density\" \"float Lescale\" 2 \"float temperaturecutoff\" 100 \"float temperaturescale\" 1000\nAttributeBegin\nMediumInterface \"hot\" \"\"\nMaterial \"interface\"\nShape \"sphere\"\nAttributeEnd\n"
    ));
    let e = d.media[0].emission.as_ref().unwrap();
    assert_eq!(
        e.temperature.as_ref().unwrap().grid.as_deref(),
        Some("density")
    );
    assert_eq!(
        (e.scale, e.temperature_offset, e.temperature_scale),
        (2.0, 100.0, 1000.0)
    );
    // pbrt-v4-scenes' spelling of Lescale.
    let d2 = desc(&format!(
        "{HEAD}MakeNamedMedium \"hot\" \"string type\" \"nanovdb\" \"string filename\" \"{file}\" \"string temperaturename\" \"density\" \"float LeScale\" 5\nMediumInterface \"hot\" \"\"\nShape \"sphere\"\n"
    ));
    assert_eq!(d2.media[0].emission.as_ref().unwrap().scale, 5.0);
}

#[test]
fn light_scale_power_and_illuminance() {
    use fogbank_render::lights::LightDesc;
    let d = desc(&format!(
        "{HEAD}LightSource \"point\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [0 1 0]\nLightSource \"point\" \"float power\" 100\nLightSource \"distant\" \"float illuminance\" 3\nLightSource \"infinite\" \"rgb L\" [0.5 0.5 0.5] \"float illuminance\" 3.14159265358979\nLightSource \"spot\" \"float coneangle\" 60 \"float conedeltaangle\" 0 \"float power\" 1\n"
    ));
    let toml = r#"
[[lights]]
type = "point"
position = [0.0, 1.0, 0.0]
intensity = [2.0, 4.0, 6.0]
[[lights]]
type = "point"
position = [0.0, 0.0, 0.0]
intensity = [7.957747154594767, 7.957747154594767, 7.957747154594767]
[[lights]]
type = "directional"
direction = [0.0, 0.0, 1.0]
irradiance = [3.0, 3.0, 3.0]
[[lights]]
type = "constant"
radiance = [0.5, 0.5, 0.5]
"#;
    let want = parse_scene(toml, "want", &[]).unwrap().lights;
    for (a, b) in d.lights.iter().zip(&want) {
        let (sa, sb) = (format!("{a:?}"), format!("{b:?}"));
        assert_eq!(sa, sb);
    }
    // A spot of 60°, no falloff band: P / (2π (1 − cos 60°)) = 1/π.
    let LightDesc::Spot { intensity, .. } = &d.lights[4] else {
        panic!("{:?}", d.lights[4]);
    };
    assert!((intensity[0] - std::f32::consts::FRAC_1_PI).abs() < 1e-6);
}

#[test]
fn area_lights_and_materials() {
    let d = desc(&format!(
        "{HEAD}AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"float power\" 3.14159265358979\nShape \"disk\" \"float radius\" 1\nAttributeEnd\nMaterial \"dielectric\" \"float eta\" 1.33\nShape \"sphere\"\nMaterial \"dielectric\" \"spectrum eta\" \"glass-BK7\"\nShape \"sphere\"\nMaterial \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\nShape \"sphere\"\nMakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.04\nNamedMaterial \"gold\"\nShape \"sphere\"\n"
    ));
    // Power π over a unit disk (area π): L = 1/π.
    let r = d.shapes[0].emitter.as_ref().unwrap().radiance;
    assert!((r[0] - std::f32::consts::FRAC_1_PI).abs() < 1e-6);
    let b1 = format!("{:?}", d.shapes[1].bsdf.as_ref().unwrap());
    assert!(b1.contains("Dielectric") && b1.contains("1.33"), "{b1}");
    let b3 = format!("{:?}", d.shapes[2].bsdf.as_ref().unwrap());
    assert!(b3.contains("bk7"), "{b3}");
    let b4 = format!("{:?}", d.shapes[3].bsdf.as_ref().unwrap());
    assert!(b4.contains("Twosided") && b4.contains("0.3"), "{b4}");
    let e = error(&format!(
        "{HEAD}Material \"diffuse\" \"rgb reflectance\" [0.1 2 0.3]\nShape \"sphere\"\n"
    ));
    assert!(e.contains("t.pbrt:5:") && e.contains("above 1"), "{e}");
    let e = error(&format!(
        "{HEAD}Material \"diffuse\" \"float reflectance\" 0.5\nShape \"sphere\"\n"
    ));
    assert!(e.contains("t.pbrt:5:") && e.contains("not used"), "{e}");
    let b2 = format!("{:?}", d.shapes[4].bsdf.as_ref().unwrap());
    assert!(b2.contains("Au") && b2.contains("0.2"), "{b2}");
}

#[test]
fn a_parallelogram_triangle_mesh_is_a_rectangle_facing_like_pbrt() {
    let d = desc(&format!(
        "{HEAD}Shape \"trianglemesh\" \"point3 P\" [-2 0 -2  2 0 -2  2 0 2  -2 0 2] \"integer indices\" [0 2 1  0 3 2]\n"
    ));
    let m = d.shapes[0].to_world.matrix.unwrap();
    // The winding 0 → 2 → 1 faces +y: the rectangle's z axis is +y.
    assert_eq!([m[0][2], m[1][2], m[2][2]], [0.0, 1.0, 0.0]);
    // Any other mesh is a PLY file (pbrt_scenes_test); a bad one is an error.
    let e = error(&format!(
        "{HEAD}Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  5 5 5] \"integer indices\" [0 1 2  1 3]\n"
    ));
    assert!(
        e.contains("t.pbrt:5:") && e.contains("not a multiple of 3"),
        "{e}"
    );
}

#[test]
fn object_instances_are_a_shape_group_and_its_instances() {
    let d = desc(&format!(
        "{HEAD}ObjectBegin \"ball\"\nShape \"sphere\" \"float radius\" 0.25\nObjectEnd\nTranslate 1 0 0\nObjectInstance \"ball\"\nTranslate 1 0 0\nObjectInstance \"ball\"\n"
    ));
    assert_eq!(d.shapes.len(), 3);
    assert_eq!(d.shapes[0].group.as_deref(), Some("ball"));
    assert_eq!(d.shapes[2].kind, fogbank_render::desc::ShapeType::Instance);
    assert_eq!(d.shapes[2].to_world.matrix.unwrap()[0][3], 2.0);
}

#[test]
fn uniform_grid_medium_is_an_in_memory_array_over_its_box() {
    let head = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 25\nFilm \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n";
    let text = format!(
        "{head}AttributeBegin\nTranslate 0 0 -1\nMakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"integer ny\" 1 \"integer nz\" 1 \"float density\" [0 1] \"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 1 1] \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [0 0 0] \"float scale\" 3\nAttributeEnd\nAttributeBegin\nMediumInterface \"g\" \"\"\nMaterial \"interface\"\nShape \"sphere\"\nAttributeEnd\nLightSource \"infinite\"\n"
    );
    let d = desc(&text);
    let m = &d.media[0];
    assert!(m.density.array.as_deref().unwrap().starts_with("array:"));
    assert_eq!((m.sigma_t_scale.max(), m.albedo), (3.0, Some([0.0; 3])));
    assert_eq!(m.to_world.matrix.unwrap()[2][3], -1.0);
    // Read again (a reload): the same array.
    assert_eq!(desc(&text).media[0].density, m.density);
    // It builds and renders: the grid's dense half (+x, on the image's
    // left) absorbs more of the environment than its empty half.
    let scene = Scene::build(d, Path::new(".")).unwrap();
    let img = render(&scene, &RenderOptions::new(64, 3), &Progress::default())
        .film
        .mean();
    let row = |x: usize| img[4 * 8 + x][0];
    assert!(row(1) < 0.5 && row(6) > 0.9, "{:?}", (row(1), row(6)));
    let e = error(&format!(
        "{HEAD}MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [1 1 1]\nMediumInterface \"g\" \"\"\nShape \"sphere\"\n"
    ));
    assert!(
        e.contains("t.pbrt:5:") && e.contains("3 density values for 2×1×1"),
        "{e}"
    );
}

/// pbrt samples a NanoVDB grid at integer index coordinates (a voxel's
/// value sits at its index point); fogbank's grids are cell-centred with
/// the half-voxel shift in the grid's transform. The same world point must
/// give the same value.
#[test]
fn nanovdb_voxels_sit_where_pbrt_puts_them() {
    let file = fixture("../../../volume/tests/fixtures/nanovdb/density_vel_zip.nvdb");
    let g = fogbank_volume::loaders::nanovdb::read_grid(&file, Some("density")).unwrap();
    // The largest active voxel, its index point mapped by the grid's
    // transform and then by the medium's (a translation).
    let mut best = (f32::MIN, [0i32; 3]);
    for leaf in &g.leaves {
        for (n, &v) in leaf.values.iter().enumerate() {
            let active = leaf.active[n / 64] >> (n % 64) & 1 == 1;
            if active && v > best.0 {
                let (x, y, z) = ((n / 64) as i32, (n / 8 % 8) as i32, (n % 8) as i32);
                best = (
                    v,
                    [leaf.origin[0] + x, leaf.origin[1] + y, leaf.origin[2] + z],
                );
            }
        }
    }
    let (v, ijk) = best;
    let m = g.index_to_world;
    let ijk = ijk.map(|c| c as f64);
    let world: [f64; 3] = std::array::from_fn(|r| {
        m[r][0] * ijk[0] + m[r][1] * ijk[1] + m[r][2] * ijk[2] + m[r][3] + [0.5, -1.0, 2.0][r]
    });
    let d = desc(&format!(
        "{HEAD}AttributeBegin\nTranslate 0.5 -1 2\nMakeNamedMedium \"smoke\" \"string type\" \"nanovdb\" \"string filename\" \"{}\"\nAttributeEnd\nMediumInterface \"\" \"smoke\"\nShape \"sphere\" \"float radius\" 0.01\n",
        file.display()
    ));
    let scene = Scene::build(d, Path::new(".")).unwrap();
    let medium = &scene.world.media[0].medium;
    let q = medium
        .world_to_index
        .transform_point3(glam::DVec3::from(world))
        .as_vec3();
    let got = medium.scalar_trilinear(q);
    assert!(
        (got - v).abs() <= 1e-5 * v.abs(),
        "{got} vs {v} at {world:?}"
    );
}

#[test]
fn attribute_defaults_apply_within_their_block() {
    let d = desc(&format!(
        "{HEAD}AttributeBegin\nAttribute \"shape\" \"float radius\" 2 \"float unused\" 1\nShape \"sphere\"\nShape \"sphere\" \"float radius\" 3\nAttributeEnd\nShape \"sphere\"\n"
    ));
    let r: Vec<f64> = d
        .shapes
        .iter()
        .map(|s| s.to_world.matrix.unwrap()[0][0])
        .collect();
    assert_eq!(r, [2.0, 3.0, 1.0]);
    let e = error(&format!("{HEAD}Attribute \"camera\" \"float fov\" 2\n"));
    assert!(e.contains("t.pbrt:5:") && e.contains("not a target"), "{e}");
}

/// Every prefix of a scene, and every one with a byte dropped, is read
/// without a panic (an error or a scene).
#[test]
fn truncated_and_damaged_scenes_never_panic() {
    let text = std::fs::read_to_string(fixture("offcentre.pbrt")).unwrap()
        + "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [0 1]\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0] \"integer indices\" [0 1 2 0 2 3]\n";
    let path = fixture("t.pbrt");
    for i in 0..text.len() {
        if !text.is_char_boundary(i) {
            continue;
        }
        let _ = load_pbrt_str(&text[..i], &path);
        let damaged = format!("{}{}", &text[..i], &text[(i + 1).min(text.len())..]);
        let _ = load_pbrt_str(&damaged, &path);
    }
}

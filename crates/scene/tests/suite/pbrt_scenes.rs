//! pbrt-v4 features beyond the grammar: `rgbgrid` and `cloud` media,
//! image infinite lights, named sensors and samplers, general inline
//! meshes, and the volumetric scenes of pbrt-v4-scenes on stand-in data.

use fogbank_render::render::{render, Progress, RenderOptions};
use fogbank_render::{parse_scene, Scene, SceneDesc};
use fogbank_scene::pbrt::{envlight, load_pbrt_str};
use glam::{DVec2, DVec3};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/pbrt")
        .join(name)
}

/// A `.pbrt` text read as if it were the file `at`.
fn desc_at(text: &str, at: &Path) -> SceneDesc {
    let t = load_pbrt_str(text, at).unwrap_or_else(|e| panic!("{e}"));
    parse_scene(&toml::to_string(&t).unwrap(), "t.pbrt", &[]).unwrap()
}

fn desc(text: &str) -> SceneDesc {
    desc_at(text, &fixture("t.pbrt"))
}

fn error(text: &str) -> String {
    match load_pbrt_str(text, &fixture("t.pbrt")) {
        Ok(_) => panic!("should fail:\n{text}"),
        Err(e) => e.0,
    }
}

fn image(d: SceneDesc, spp: u32) -> Vec<[f32; 3]> {
    let scene = Scene::build(d, Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
    render(&scene, &RenderOptions::new(spp, 3), &Progress::default())
        .film
        .mean()
}

fn mean(img: &[[f32; 3]]) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in img {
        for c in 0..3 {
            m[c] += p[c] as f64 / img.len() as f64;
        }
    }
    m
}

/// A fresh folder for files a test writes.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fogbank-pbrt-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

macro_rules! cam {
    () => {
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\nFilm \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n"
    };
}
const CAM: &str = cam!();
const HEAD: &str = concat!(cam!(), "LightSource \"infinite\"\n");

fn grid_medium(params: &str) -> String {
    format!("{HEAD}AttributeBegin\nMakeNamedMedium \"g\" \"string type\" \"rgbgrid\" \"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 1 1] {params}\nAttributeEnd\nAttributeBegin\nMediumInterface \"g\" \"\"\nMaterial \"interface\"\nShape \"sphere\" \"float radius\" 1.8\nAttributeEnd\n")
}

#[test]
fn rgbgrid_chromatic_extinction_is_a_three_channel_density() {
    let d = desc(&grid_medium(
        "\"integer nx\" 2 \"rgb sigma_a\" [1 2 3 1 2 3] \"rgb sigma_s\" [1 1 1 1 1 1] \"float scale\" 2",
    ));
    let m = &d.media[0];
    assert!(m.density_rgb);
    assert!(m.density.array.is_some());
    assert_eq!(m.sigma_t_scale.max(), 2.0);
    let a = m.albedo.unwrap();
    assert!(
        (a[0] - 0.5).abs() < 1e-6 && (a[2] - 0.25).abs() < 1e-6,
        "{a:?}"
    );
    assert!(m.albedo_grid.is_none());
    // Red (σ_t = 4) passes more of the environment than blue (σ_t = 8).
    let img = image(d, 16);
    let c = img[4 * 8 + 4];
    assert!(c.iter().all(|v| v.is_finite()) && c[0] > c[2], "{c:?}");
}

#[test]
fn rgbgrid_varying_albedo_and_emission() {
    let d = desc(&grid_medium(
        "\"integer nx\" 2 \"rgb sigma_a\" [1 1 1 3 3 3] \"rgb sigma_s\" [3 3 3 1 1 1] \"rgb Le\" [0 0 0 5 4 3] \"float Lescale\" 2",
    ));
    let m = &d.media[0];
    assert!(!m.density_rgb, "grey σ_t in every voxel");
    assert_eq!(m.albedo, Some([1.0; 3]));
    assert!(m.albedo_grid.as_ref().unwrap().array.is_some());
    let e = m.emission.as_ref().unwrap();
    assert_eq!(e.scale, 2.0);
    assert!(e.grid.as_ref().unwrap().array.is_some());
    assert!(image(d, 4).iter().flatten().all(|v| v.is_finite()));
    // A missing σ grid is 1, as pbrt's; errors name the line.
    let d = desc(&grid_medium("\"rgb sigma_s\" [0 0 0]"));
    assert_eq!(d.media[0].albedo, Some([0.0; 3]));
    let e = error(&grid_medium("\"rgb sigma_s\" [1 1 1] \"rgb Le\" [1 1 1]"));
    assert!(
        e.contains("t.pbrt:7:") && e.contains("\"Le\" needs \"sigma_a\""),
        "{e}"
    );
    let e = error(&grid_medium("\"integer nx\" 2 \"rgb sigma_a\" [1 1 1]"));
    assert!(e.contains("1 values for 2×1×1"), "{e}");
}

#[test]
fn cloud_density_is_pbrts_and_is_baked_over_its_box() {
    use fogbank_scene::pbrt::cloud::{noise, Cloud};
    // Perlin noise vanishes on the lattice and stays within ±1.
    assert_eq!(noise(DVec3::new(3.0, -7.0, 12.0)), 0.0);
    for i in 0..200 {
        let p = DVec3::new(i as f64 * 0.37, i as f64 * -0.21, i as f64 * 0.13);
        assert!(noise(p).abs() <= 1.0);
    }
    let c = Cloud {
        density: 1.0,
        wispiness: 1.0,
        frequency: 5.0,
    };
    // Below the base it is solid; elsewhere within [0, 1], and not constant.
    assert_eq!(c.density(DVec3::new(0.3, -0.1, 0.7)), 1.0);
    let v: Vec<f64> = (0..50)
        .map(|i| c.density(DVec3::new(0.3 + 0.01 * i as f64, 0.6, 0.7)))
        .collect();
    assert!(v.iter().all(|x| (0.0..=1.0).contains(x)));
    assert!(v.iter().any(|&x| x != v[0]), "{v:?}");
    let text = format!("{HEAD}MakeNamedMedium \"c\" \"string type\" \"cloud\" \"spectrum sigma_a\" [200 .01 900 .01] \"spectrum sigma_s\" [200 10 900 10] \"float density\" 2\nAttributeBegin\nMediumInterface \"c\" \"\"\nMaterial \"interface\"\nTranslate .5 .5 .5\nShape \"sphere\"\nAttributeEnd\n");
    let t = load_pbrt_str(&text, &fixture("t.pbrt")).unwrap();
    let d = desc(&text);
    let m = &d.media[0];
    assert!(m.density.array.is_some());
    assert!((m.sigma_t_scale.max() - 10.01).abs() < 1e-3);
    assert!(t.contains_key("media"));
    assert!(image(d, 2).iter().flatten().all(|v| v.is_finite()));
    let e = error(&format!("{HEAD}MakeNamedMedium \"c\" \"string type\" \"cloud\" \"float scale\" 2\nMediumInterface \"c\" \"\"\nShape \"sphere\"\n"));
    assert!(e.contains("has no \"scale\""), "{e}");
    assert_eq!(
        fogbank_scene::pbrt::cloud::resolution(DVec3::ZERO, DVec3::ONE, 5.0),
        [80; 3]
    );
}

#[test]
fn equal_area_square_maps_round_trip() {
    for i in 0..500 {
        // Inside the square: its edges fold onto each other.
        let f = |x: f64| 0.001 + 0.998 * (x % 1.0);
        let u = DVec2::new(f(i as f64 * 0.618034), f(i as f64 * 0.381966 + 0.1));
        let d = envlight::square_to_sphere(u);
        assert!((d.length() - 1.0).abs() < 1e-9);
        let back = envlight::sphere_to_square(d);
        assert!((back - u).length() < 1e-9, "{u} → {d} → {back}");
    }
    // +z is the square's centre, −z its corners.
    assert!((envlight::square_to_sphere(DVec2::splat(0.5)) - DVec3::Z).length() < 1e-12);
    assert!((envlight::square_to_sphere(DVec2::ZERO) + DVec3::Z).length() < 1e-12);
}

/// An `n`×`n` octahedral map, `bright` within `radius` (radians) of the
/// light-space direction `centre` and `base` elsewhere, written as EXR.
fn octahedral(path: &Path, n: usize, centre: DVec3, radius: f64, bright: f32, base: f32) {
    let mut px = vec![[base; 3]; n * n];
    for y in 0..n {
        for x in 0..n {
            let d = envlight::square_to_sphere(DVec2::new(
                (x as f64 + 0.5) / n as f64,
                (y as f64 + 0.5) / n as f64,
            ));
            if d.angle_between(centre) < radius {
                px[y * n + x] = [bright; 3];
            }
        }
    }
    fogbank_image::image_io::write_exr(path, n as u32, n as u32, &px, None).unwrap();
}

#[test]
fn image_infinite_light_puts_light_where_pbrt_does() {
    use fogbank_render::lights::envmap::Envmap;
    use fogbank_render::lights::LightDesc;
    let dir = temp_dir("envlight");
    let sky = dir.join("sky.exr");
    // Bright around light-space +x; the light rotated 90° about z puts it
    // at world +y.
    octahedral(&sky, 64, DVec3::X, 0.3, 100.0, 0.0);
    let text = format!("{CAM}AttributeBegin\nRotate 90 0 0 1\nLightSource \"infinite\" \"string filename\" \"sky.exr\" \"float scale\" 2\nAttributeEnd\n");
    let d = desc_at(&text, &dir.join("t.pbrt"));
    let LightDesc::Envmap {
        file,
        scale,
        rotate,
        ..
    } = &d.lights[0]
    else {
        panic!("{:?}", d.lights[0]);
    };
    assert_eq!((*scale, *rotate), (2.0, None));
    let env = Envmap::load(Path::new(file), 1.0, glam::Mat3::IDENTITY).unwrap();
    let at = |v: [f32; 3]| env.eval(glam::Vec3::from(v).normalize()).x;
    assert!(at([0.0, 1.0, 0.0]) > 50.0, "{}", at([0.0, 1.0, 0.0]));
    for v in [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ] {
        assert_eq!(at(v), 0.0, "{v:?}");
    }
    // The power is kept: ∫L dω of the lat-long map is the octahedral one's.
    let (w, h) = (env.width(), env.height());
    let mut total = 0.0;
    for i in 0..h {
        let (t0, t1) = (
            i as f64 * std::f64::consts::PI / h as f64,
            (i + 1) as f64 * std::f64::consts::PI / h as f64,
        );
        for j in 0..w {
            let phi = (j as f64 + 0.5) * 2.0 * std::f64::consts::PI / w as f64;
            let th = 0.5 * (t0 + t1);
            let dir = glam::Vec3::new(
                (th.sin() * phi.sin()) as f32,
                th.cos() as f32,
                (-th.sin() * phi.cos()) as f32,
            );
            total += env.eval(dir).x as f64 * (t0.cos() - t1.cos()) * 2.0 * std::f64::consts::PI
                / w as f64;
        }
    }
    let mut expected = 0.0;
    let n = 64;
    for y in 0..n {
        for x in 0..n {
            let d = envlight::square_to_sphere(DVec2::new(
                (x as f64 + 0.5) / n as f64,
                (y as f64 + 0.5) / n as f64,
            ));
            if d.angle_between(DVec3::X) < 0.3 {
                expected += 100.0 * 4.0 * std::f64::consts::PI / (n * n) as f64;
            }
        }
    }
    assert!(
        (total / expected - 1.0).abs() < 0.03,
        "{total} vs {expected}"
    );
}

#[test]
fn a_uniform_image_light_renders_as_a_uniform_light() {
    let dir = temp_dir("envuniform");
    octahedral(&dir.join("one.exr"), 16, DVec3::Z, 0.0, 0.0, 0.5);
    let scene = |light: &str| format!("{CAM}{light}\nShape \"sphere\"\n");
    let a = mean(&image(
        desc_at(
            &scene("LightSource \"infinite\" \"string filename\" \"one.exr\" \"float scale\" 2"),
            &dir.join("t.pbrt"),
        ),
        64,
    ));
    let b = mean(&image(
        desc_at(
            &scene("LightSource \"infinite\" \"rgb L\" [1 1 1]"),
            &dir.join("t.pbrt"),
        ),
        64,
    ));
    for c in 0..3 {
        assert!((a[c] / b[c] - 1.0).abs() < 0.03, "{a:?} vs {b:?}");
    }
    // `illuminance` as pbrt computes it: 2π/N² Σ Y cos θ above the horizon.
    let d = desc_at(
        &scene("LightSource \"infinite\" \"string filename\" \"one.exr\" \"float illuminance\" 10"),
        &dir.join("t.pbrt"),
    );
    let fogbank_render::lights::LightDesc::Envmap { scale, .. } = &d.lights[0] else {
        panic!()
    };
    let px = vec![[0.5f32; 3]; 256];
    let k = envlight::Square { n: 16, rgb: &px }.illuminance();
    assert!(
        (*scale as f64 - 10.0 / k).abs() < 1e-4 * (10.0 / k),
        "{scale} vs {}",
        10.0 / k
    );
}

#[test]
fn named_sensors_iso_and_samplers_are_accepted() {
    let d = desc("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float shutterclose\" 0.5\nFilm \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"string sensor\" \"nikon_d850\" \"float iso\" 400 \"float whitebalance\" 5000 \"float maxcomponentvalue\" 20\nSampler \"halton\" \"integer pixelsamples\" 7\nWorldBegin\n");
    // Imaging ratio 0.5 · 400 / 100 = 2: one stop.
    assert_eq!((d.render.exposure, d.render.spp), (1.0, 7));
    let d = desc("Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 2 \"bool jitter\" false\nWorldBegin\n");
    assert_eq!((d.render.exposure, d.render.spp), (0.0, 6));
    for s in ["sobol", "zsobol", "pmj02bn", "independent"] {
        let d = desc(&format!("Sampler \"{s}\" \"integer pixelsamples\" 3 \"string randomization\" \"owen\" \"integer seed\" 5\nWorldBegin\n"));
        assert_eq!(d.render.spp, 3);
    }
    let e = error("Sampler \"magic\"\nWorldBegin\n");
    assert!(
        e.contains("t.pbrt:1:") && e.contains("\"magic\" is unknown"),
        "{e}"
    );
    let e = error("Camera \"perspective\" \"float shutteropen\" 1\nWorldBegin\n");
    assert!(e.contains("imaging ratio"), "{e}");
}

#[test]
fn inline_meshes_become_ply_files() {
    // Two triangles that are no parallelogram, one with normals: a PLY.
    let d = desc(&format!("{HEAD}AreaLightSource \"diffuse\" \"float power\" 1\nShape \"trianglemesh\" \"point3 P\" [0 0 0 2 0 0 0 1 0 2 1 1] \"integer indices\" [0 1 2 1 3 2]\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 1 0 0 1 0 0 1] \"point2 uv\" [0 0 1 0 0 1]\n"));
    use fogbank_render::world::surfaces::shape::ShapeType;
    assert_eq!(d.shapes[0].kind, ShapeType::Ply);
    assert!(d.shapes[0].face_normals && !d.shapes[1].face_normals);
    // power P over the mesh's area A: radiance P/(πA).
    let area = 1.0 + 1.5;
    let l = d.shapes[0].emitter.as_ref().unwrap().radiance[0] as f64;
    assert!(
        (l - 1.0 / (std::f64::consts::PI * area)).abs() < 1e-5,
        "{l}"
    );
    let mesh =
        fogbank_geometry::load_mesh(Path::new(d.shapes[1].file.as_deref().unwrap())).unwrap();
    assert_eq!(
        (mesh.triangles.len(), mesh.normals.len(), mesh.uvs.len()),
        (1, 3, 3)
    );
    // Bilinear patches: a planar pair is 4 triangles, a curved one 2·8².
    let d = desc(&format!("{HEAD}Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0 2 0 0 2 1 0] \"integer indices\" [0 1 2 3 1 4 3 5]\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 1]\n"));
    let count = |i: usize| {
        fogbank_geometry::load_mesh(Path::new(d.shapes[i].file.as_deref().unwrap()))
            .unwrap()
            .triangles
            .len()
    };
    assert_eq!((count(0), count(1)), (4, 128));
    // pbrt's facing: the planar patches' normal is +z (∂p/∂u × ∂p/∂v).
    let m = fogbank_geometry::load_mesh(Path::new(d.shapes[0].file.as_deref().unwrap())).unwrap();
    let t = m.triangles[0];
    let [a, b, c] = t.map(|i| m.positions[i as usize]);
    assert!((b - a).cross(c - a).z > 0.0);
    assert!(image(d, 2).iter().flatten().all(|v| v.is_finite()));
    let e = error(&format!("{HEAD}Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 1] \"integer indices\" [0 1 7]\n"));
    assert!(e.contains("t.pbrt:6:") && e.contains("outside 0..4"), "{e}");
}

/// Copies the folder `from` into `to`.
fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

/// A sky in pbrt's equal-area octahedral layout: blue above the horizon
/// (+z of the light's frame), brighter towards the zenith, grey below.
fn sky(path: &Path) {
    let n = 32;
    let mut px = Vec::new();
    for y in 0..n {
        for x in 0..n {
            let d = envlight::square_to_sphere(DVec2::new(
                (x as f64 + 0.5) / n as f64,
                (y as f64 + 0.5) / n as f64,
            ));
            let z = d.z as f32;
            px.push(if z > 0.0 {
                [0.3 + z, 0.5 + z, 1.0 + z]
            } else {
                [0.2; 3]
            });
        }
    }
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    fogbank_image::image_io::write_exr(path, n as u32, n as u32, &px, None).unwrap();
}

/// A NanoVDB file of a procedural cloud (`res`³ voxels) spanning the box
/// `lo`–`hi`, as `density` and, if `temperature` > 0, as a temperature
/// grid of that many kelvin per unit of density.
fn nvdb(path: &Path, res: u32, lo: DVec3, hi: DVec3, temperature: f32) {
    use fogbank_volume::writers::{self, Codec, NanoOptions, NanoValue};
    let g = fogbank_volume::procedural::cloud_grid::<f32>(res, 3).unwrap();
    let size = (hi - lo) / res as f64;
    let xf =
        fogbank_math::DAffine3::from_translation(lo) * fogbank_math::DAffine3::from_scale(size);
    let mut grids = vec![writers::from_brick_grid(&g, xf, "density", 0.0)];
    if temperature > 0.0 {
        let t = g.map_values(|v| v * temperature);
        grids.push(writers::from_brick_grid(&t, xf, "temperature", 0.0));
    }
    let options = NanoOptions {
        value: NanoValue::Float,
        codec: Codec::Zip,
    };
    writers::nanovdb::write(path, &grids, options).unwrap();
}

/// An ASCII PLY of the quads `q` (four corners each).
fn ply(path: &Path, q: &[[[f64; 3]; 4]]) {
    let mut s = format!("ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n", 4 * q.len(), q.len());
    for quad in q {
        for p in quad {
            s += &format!("{} {} {}\n", p[0], p[1], p[2]);
        }
    }
    for i in 0..q.len() {
        s += &format!("4 {} {} {} {}\n", 4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3);
    }
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, s).unwrap();
}

/// The six faces of the box `a`–`b`, outward.
fn box_quads(a: [f64; 3], b: [f64; 3]) -> Vec<[[f64; 3]; 4]> {
    let [x0, y0, z0] = a;
    let [x1, y1, z1] = b;
    vec![
        [[x0, y0, z0], [x0, y1, z0], [x1, y1, z0], [x1, y0, z0]],
        [[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],
        [[x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]],
        [[x0, y1, z0], [x0, y1, z1], [x1, y1, z1], [x1, y1, z0]],
        [[x0, y0, z0], [x0, y0, z1], [x0, y1, z1], [x0, y1, z0]],
        [[x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1]],
    ]
}

/// Writes the stand-in data files of the scene folder `dir` (see
/// `tests/pbrt/v4-scenes/README.md`).
fn stand_ins(name: &str, dir: &Path) {
    if name != "disney-cloud" {
        sky(&dir.join("textures/sky.exr"));
    }
    match name {
        "explosion" => nvdb(
            &dir.join("fire.nvdb"),
            16,
            DVec3::splat(-30.0),
            DVec3::splat(30.0),
            25.0,
        ),
        "bunny-cloud" => nvdb(
            &dir.join("bunny_cloud.nvdb"),
            16,
            DVec3::splat(-30.0),
            DVec3::splat(30.0),
            0.0,
        ),
        "disney-cloud" => {
            let c = DVec3::new(-9.984, 73.008, -42.64);
            let h = DVec3::new(206.544, 140.4, 254.592) / 2.0;
            nvdb(&dir.join("wdas_cloud_quarter.nvdb"), 16, c - h, c + h, 0.0);
        }
        "dambreak" => {
            let g = dir.join("geometry");
            let walls = [
                ([1.08, 0.1, 63.14], [126.96, 64.04, 64.14]),
                ([1.08, 0.15, 1.17], [126.96, 1.15, 63.12]),
                ([1.08, 0.1, 0.21], [126.96, 64.04, 1.21]),
                ([126.95, 0.1, 0.2], [127.95, 64.04, 64.14]),
                ([0.08, 0.1, 0.2], [1.08, 64.04, 64.14]),
                ([1.08, 63.0, 1.17], [126.96, 64.0, 63.12]),
            ];
            for (i, (a, b)) in walls.iter().enumerate() {
                ply(
                    &g.join(format!("mesh_0000{}.ply", i + 1)),
                    &box_quads(*a, *b),
                );
            }
            ply(
                &g.join("mesh_00008.ply"),
                &[[
                    [-368.5, 0.03, -219.6],
                    [-368.5, 0.03, 153.8],
                    [518.2, 0.03, 153.8],
                    [518.2, 0.03, -219.6],
                ]],
            );
            ply(
                &g.join("dambreak0.ply"),
                &box_quads([2.0, 1.2, 2.0], [40.0, 40.0, 62.0]),
            );
        }
        _ => {}
    }
}

/// Each pbrt-v4-scenes volumetric scene, on stand-in data, reads (every
/// approximation a notice, nothing refused) and renders a tiny image that
/// is finite and not black.
#[test]
fn pbrt_v4_scenes_parse_and_render() {
    let scenes = [
        ("explosion", "explosion.pbrt", (18, 24)),
        ("bunny-cloud", "bunny-cloud.pbrt", (24, 14)),
        ("disney-cloud", "disney-cloud.pbrt", (24, 14)),
        ("clouds", "clouds.pbrt", (24, 14)),
        ("smoke-plume", "plume.pbrt", (16, 16)),
        ("dambreak", "dambreak0.pbrt", (24, 14)),
    ];
    let root = temp_dir("v4-scenes");
    for (name, file, (w, h)) in scenes {
        let dir = root.join(name);
        copy_tree(&fixture("v4-scenes").join(name), &dir);
        stand_ins(name, &dir);
        let t = fogbank_scene::pbrt::load_pbrt(&dir.join(file))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let sets = [
            format!("camera.width={w}"),
            format!("camera.height={h}"),
            "render.spp=2".to_string(),
            "integrator.max_depth=4".to_string(),
        ];
        let d = parse_scene(&toml::to_string(&t).unwrap(), file, &sets)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        check_scene(name, &d);
        let img = image(d, 2);
        let m = mean(&img);
        assert!(img.iter().flatten().all(|v| v.is_finite()), "{name}");
        assert!(m.iter().sum::<f64>() > 0.0, "{name}: black");
        eprintln!("{name}: mean {m:?}");
    }
}

/// What each pbrt-v4-scenes scene's conversion must hold.
fn check_scene(name: &str, d: &SceneDesc) {
    use fogbank_render::lights::LightDesc;
    use fogbank_render::world::surfaces::shape::ShapeType;
    let envmap = d
        .lights
        .iter()
        .any(|l| matches!(l, LightDesc::Envmap { .. }));
    assert_eq!(envmap, name != "disney-cloud", "{name}");
    let m = &d.media[0];
    match name {
        // σ_s = σ_a = 10 (a constant spectrum), blackbody emission.
        "explosion" => {
            assert_eq!(m.sigma_t_scale.max(), 20.0);
            let e = m.emission.as_ref().unwrap();
            assert_eq!(
                (e.scale, e.temperature_offset, e.temperature_scale),
                (5.0, 1.0, 100.0)
            );
        }
        "bunny-cloud" => assert!((m.sigma_t_scale.max() - 10.5).abs() < 1e-4),
        "disney-cloud" => {
            assert_eq!((m.sigma_t_scale.max(), m.albedo), (4.0, Some([1.0; 3])));
            assert!(
                d.shapes.iter().any(|s| s.kind == ShapeType::Ply),
                "the ellipsoid"
            );
        }
        "clouds" => assert!(m.density.array.is_some()),
        // The uniformgrid's parameters continue after the Include.
        "smoke-plume" => {
            assert!(m.density.array.is_some());
            assert_eq!(m.sigma_t_scale.max(), 180.0);
        }
        "dambreak" => assert!(d.shapes.iter().filter(|s| s.kind == ShapeType::Ply).count() == 8),
        _ => unreachable!(),
    }
}

/// An rgbgrid's voxels sit where pbrt's `SampledGrid::Lookup` puts them:
/// cell-centred over p0–p1, interpolated between centres.
#[test]
fn rgbgrid_voxels_sit_where_pbrt_puts_them() {
    let d = desc(&grid_medium(
        "\"integer nx\" 2 \"rgb sigma_a\" [1 1 1 3 3 3] \"rgb sigma_s\" [0 0 0 0 0 0]",
    ));
    let scene = Scene::build(d, Path::new(".")).unwrap();
    let m = &scene.world.media[0].medium;
    // Lookup coordinate (x + 1)/2 · 2 − ½: voxel centres at x = ∓½.
    for (x, want) in [(-0.5, 1.0), (0.0, 2.0), (0.5, 3.0), (0.25, 2.5)] {
        let q = m
            .world_to_index
            .transform_point3(DVec3::new(x, 0.3, -0.2))
            .as_vec3();
        let got = m.scalar_trilinear(q);
        assert!((got - want).abs() < 1e-5, "x = {x}: {got} vs {want}");
    }
}

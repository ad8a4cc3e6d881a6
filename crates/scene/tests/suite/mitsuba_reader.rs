//! Mitsuba 3 XML read as Mitsuba itself reads it: file names resolved as
//! its `FileResolver` does, the perspective sensor's defaults (focal
//! length, fov axes, clip planes) and `<spectrum>` values, each compared
//! with what Mitsuba 3 computes for the same XML
//! (`fixtures/mitsuba_reader_facts.json`, written by
//! `tools/mitsuba_reader_facts.py` with Mitsuba 3.9.1 `scalar_rgb`).

use fogbank_render::parse_scene;
use fogbank_scene::load_scene;
use fogbank_scene::mitsuba::load_xml_str;
use serde_json::Value as Json;
use std::path::{Path, PathBuf};

fn facts() -> Json {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mitsuba_reader_facts.json");
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fogbank-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn f32s(v: &Json) -> Vec<f32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

const TRIANGLE_OBJ: &str = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";

/// `a.xml` includes `include/base.xml`, which includes
/// `include/preamble.xml` (found beside `base.xml`, the including file) and
/// loads `meshes/tri.obj` — found beside `a.xml`, the top-level file, as in
/// Mitsuba, although `base.xml` names it.
#[test]
fn nested_includes_and_meshes_resolve_from_the_top_level_file() {
    let dir = temp_dir("mitsuba-tree");
    std::fs::create_dir_all(dir.join("include")).unwrap();
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/tri.obj"), TRIANGLE_OBJ).unwrap();
    std::fs::write(
        dir.join("include/preamble.xml"),
        "<scene version=\"3.0.0\"><default name=\"spp\" value=\"3\"/>\
         <bsdf type=\"diffuse\" id=\"grey\"><rgb name=\"reflectance\" value=\"0.4\"/></bsdf></scene>",
    )
    .unwrap();
    std::fs::write(
        dir.join("include/base.xml"),
        "<scene version=\"3.0.0\"><include filename=\"preamble.xml\"/>\
         <sensor type=\"perspective\"><transform name=\"to_world\"><lookat origin=\"0, 0, 4\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>\
         <sampler type=\"independent\"><integer name=\"sample_count\" value=\"$spp\"/></sampler>\
         <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"6\"/><rfilter type=\"box\"/></film></sensor>\
         <shape type=\"obj\"><string name=\"filename\" value=\"meshes/tri.obj\"/><ref id=\"grey\"/></shape></scene>",
    )
    .unwrap();
    std::fs::write(
        dir.join("a.xml"),
        "<scene version=\"3.0.0\"><include filename=\"include/base.xml\"/>\
         <emitter type=\"constant\"><rgb name=\"radiance\" value=\"1\"/></emitter></scene>",
    )
    .unwrap();
    let scene = load_scene(Some(&dir.join("a.xml")), &[]).unwrap();
    assert_eq!(scene.camera.width, 8);

    // A mesh only beside the included file is not found, as in Mitsuba.
    std::fs::create_dir_all(dir.join("include/meshes")).unwrap();
    std::fs::write(dir.join("include/meshes/only_here.obj"), TRIANGLE_OBJ).unwrap();
    let base = std::fs::read_to_string(dir.join("include/base.xml")).unwrap();
    std::fs::write(
        dir.join("include/base.xml"),
        base.replace("meshes/tri.obj", "meshes/only_here.obj"),
    )
    .unwrap();
    let e = load_scene(Some(&dir.join("a.xml")), &[]).err().unwrap().0;
    assert!(
        e.contains("only_here.obj") && e.contains("top-level scene's folder"),
        "{e}"
    );

    // A <path> in the top-level file is searched first.
    let a = std::fs::read_to_string(dir.join("a.xml")).unwrap();
    std::fs::write(
        dir.join("a.xml"),
        a.replace("<include", "<path value=\"include\"/><include"),
    )
    .unwrap();
    load_scene(Some(&dir.join("a.xml")), &[]).unwrap();
}

/// The camera's rays through the film's corners and centre are Mitsuba's
/// `sensor.sample_ray` rays: the same origin on the near plane and unit
/// direction to 1e-5 and the same length to the far plane, for the default
/// 50 mm focal length, other focal lengths, every `fov_axis`, both aspect
/// ratios, and near and far clip planes (given and default).
#[test]
fn sensors_give_mitsubas_rays() {
    let f = facts();
    for case in f["sensors"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let xml = format!(
            "<scene version=\"3.0.0\">{}</scene>",
            case["xml"].as_str().unwrap()
        );
        let table = load_xml_str(&xml, Path::new("sensor.xml"), &[]).unwrap();
        let desc = parse_scene(&toml::to_string(&table).unwrap(), name, &[]).unwrap();
        let camera = desc.camera.build().unwrap();
        let (w, h) = (camera.width as f32, camera.height as f32);
        for ray in case["rays"].as_array().unwrap() {
            let s = f32s(&ray["sample"]);
            let r = camera.ray(s[0] * w, s[1] * h);
            let (d, o) = (f32s(&ray["d"]), f32s(&ray["o"]));
            for c in 0..3 {
                assert!(
                    (r.d[c] - d[c]).abs() < 1e-5 && (r.o[c] - o[c]).abs() < 1e-5,
                    "{name} at {s:?}: ray {r:?}, Mitsuba o {o:?} d {d:?}"
                );
            }
            let (end, maxt) = (camera.ray_end(&r), ray["maxt"].as_f64().unwrap() as f32);
            assert!(
                (end - maxt).abs() <= 1e-5 * maxt,
                "{name} at {s:?}: ends at {end}, Mitsuba's maxt {maxt}"
            );
        }
    }
}

/// Finds the first value under `key` anywhere in a TOML tree.
fn find<'a>(v: &'a toml::Value, key: &str) -> Option<&'a toml::Value> {
    match v {
        toml::Value::Table(t) => t.get(key).or_else(|| t.values().find_map(|x| find(x, key))),
        toml::Value::Array(a) => a.iter().find_map(|x| find(x, key)),
        _ => None,
    }
}

/// `<spectrum>` values (wavelength:value lists and constants) on an
/// emitter, a reflectance, a conductor's η, a medium's σ_t and albedo and a
/// constant volume become the RGB values Mitsuba's `scalar_rgb` stores, to
/// 1e-4.
#[test]
fn spectra_become_mitsubas_rgb() {
    let f = facts();
    let key = |ctx: &str| match ctx {
        "emitter" => "radiance",
        "reflectance" => "reflectance",
        "unbounded" => "eta",
        "sigma_t" | "constvolume" => "sigma_t_scale",
        "albedo" => "albedo",
        other => panic!("context {other}"),
    };
    let mut checked = 0;
    for case in f["spectra"].as_array().unwrap() {
        let ctx = case["context"].as_str().unwrap();
        // volpath: Mitsuba's default integrator (path) would drop the media.
        let xml = format!(
            "<scene version=\"3.0.0\"><integrator type=\"volpath\"/>{}</scene>",
            case["xml"].as_str().unwrap()
        );
        let table = toml::Value::Table(load_xml_str(&xml, Path::new("s.xml"), &[]).unwrap());
        let got: Vec<f32> = match find(&table, key(ctx)).unwrap() {
            toml::Value::Array(a) => a.iter().map(|x| x.as_float().unwrap() as f32).collect(),
            x => vec![x.as_float().unwrap() as f32; 3],
        };
        let want = f32s(&case["rgb"]);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 1e-4,
                "{ctx} {}: {got:?}, Mitsuba {want:?}",
                case["value"]
            );
        }
        checked += 1;
    }
    assert!(checked >= 40, "{checked}");
}

/// Malformed spectra are errors naming the element, not panics.
#[test]
fn malformed_spectra_name_their_element() {
    for bad in [
        "400:1",
        "400:1, 300:2",
        "400:0.5, x:1",
        "400:1:2, 500:1",
        "500:1, 0.5",
    ] {
        let xml = format!(
            "<scene version=\"3.0.0\">\n<shape type=\"rectangle\"><bsdf type=\"diffuse\">\n\
             <spectrum name=\"reflectance\" value=\"{bad}\"/></bsdf></shape></scene>"
        );
        let e = load_xml_str(&xml, Path::new("bad.xml"), &[]).unwrap_err().0;
        assert!(
            e.contains("bad.xml:3") && e.contains("spectrum"),
            "{bad}: {e}"
        );
    }
    // Blackbody spectra: Mitsuba's RGB variants refuse them, and so does fogbank.
    let xml = "<scene version=\"3.0.0\">\n<shape type=\"rectangle\"><emitter type=\"area\">\n\
               <spectrum type=\"blackbody\" name=\"radiance\"><float name=\"temperature\" value=\"3000\"/></spectrum>\n\
               </emitter></shape></scene>";
    let e = load_xml_str(xml, Path::new("bb.xml"), &[]).unwrap_err().0;
    assert!(e.contains("bb.xml:3") && e.contains("RGB variants"), "{e}");
}

fn scene_xml(body: &str) -> toml::Value {
    let xml = format!("<scene version=\"3.0.0\">{body}</scene>");
    toml::Value::Table(load_xml_str(&xml, Path::new("t.xml"), &[]).unwrap())
}

const FOG_IN_SPHERE: &str =
    "<medium type=\"homogeneous\" id=\"m\"><float name=\"sigma_t\" value=\"2\"/></medium>\
     <shape type=\"sphere\"><bsdf type=\"diffuse\"/><ref name=\"interior\" id=\"m\"/></shape>";

/// Mitsuba's `path` and `direct` integrators, and its default (`path`)
/// when a scene names none, render without media; `direct` stops at the
/// first surface (Mitsuba's max_depth 2); `volpath` keeps the media.
#[test]
fn path_and_direct_integrators_ignore_media() {
    let media = |v: &toml::Value| v["media"].as_array().unwrap().len();
    let depth = |v: &toml::Value| v["integrator"]["max_depth"].as_integer().unwrap();
    let none = scene_xml(FOG_IN_SPHERE);
    assert_eq!((media(&none), depth(&none)), (0, 100_000));
    let path = scene_xml(&format!("<integrator type=\"path\"/>{FOG_IN_SPHERE}"));
    assert_eq!(media(&path), 0);
    let direct = scene_xml(&format!("<integrator type=\"direct\"><integer name=\"emitter_samples\" value=\"4\"/></integrator>{FOG_IN_SPHERE}"));
    assert_eq!((media(&direct), depth(&direct)), (0, 1));
    let volpath = scene_xml(&format!("<integrator type=\"volpath\"/>{FOG_IN_SPHERE}"));
    assert_eq!(media(&volpath), 1);
    // A null surface counts as a bounce in Mitsuba's path, not in fogbank:
    // refused with a finite depth, accepted without one.
    let null = "<shape type=\"sphere\"><bsdf type=\"null\"/></shape>";
    let e = load_xml_str(
        &format!("<scene version=\"3.0.0\"><integrator type=\"path\"><integer name=\"max_depth\" value=\"5\"/></integrator>{null}</scene>"),
        Path::new("t.xml"),
        &[],
    )
    .unwrap_err()
    .0;
    assert!(
        e.contains("counts a passage") || e.contains("count a passage"),
        "{e}"
    );
    scene_xml(&format!("<integrator type=\"path\"/>{null}"));
}

/// Emitters default to 1, as in Mitsuba.
#[test]
fn emitters_default_to_one() {
    let v = scene_xml(
        "<emitter type=\"constant\"/><shape type=\"rectangle\"><emitter type=\"area\"/></shape>",
    );
    assert_eq!(
        v["lights"][0]["radiance"].as_array().unwrap()[1].as_float(),
        Some(1.0)
    );
    assert_eq!(
        find(&v["shapes"], "radiance").unwrap().as_array().unwrap()[0].as_float(),
        Some(1.0)
    );
}

/// A conductor `material` is Mitsuba's RGB (η, k) of that metal; giving
/// both a material and η is an error, as in Mitsuba.
#[test]
fn named_conductors_are_mitsubas() {
    use fogbank_render::world::surfaces::conductors::conductor;
    let (eta, k) = conductor("Au").unwrap();
    // Mitsuba 3.9.1's traverse of `conductor` with material Au.
    let (m_eta, m_k) = ([0.143036, 0.375307, 1.44205], [3.983, 2.38556, 1.60336]);
    for c in 0..3 {
        assert!((eta[c] - m_eta[c]).abs() < 1e-5 && (k[c] - m_k[c]).abs() < 1e-5);
    }
    let v = scene_xml("<shape type=\"rectangle\"><bsdf type=\"roughconductor\"><string name=\"material\" value=\"Cu\"/></bsdf></shape>");
    let text = toml::to_string(&v).unwrap();
    let desc = parse_scene(&text, "t", &[]).unwrap();
    let scene = fogbank_render::Scene::build(desc, Path::new(".")).unwrap();
    let s = scene.world.surfaces.as_ref().unwrap();
    let bsdf = format!("{:?}", s.shapes[0].material.front.bsdf);
    assert!(bsdf.contains("0.201005"), "{bsdf}");
    let e = load_xml_str(
        "<scene version=\"3.0.0\"><shape type=\"rectangle\"><bsdf type=\"conductor\"><string name=\"material\" value=\"Unobtainium\"/></bsdf></shape></scene>",
        Path::new("t.xml"),
        &[],
    )
    .map(|t| {
        let desc = parse_scene(&toml::to_string(&t).unwrap(), "t", &[]).unwrap();
        fogbank_render::Scene::build(desc, Path::new(".")).err().unwrap().0
    })
    .unwrap();
    assert!(e.contains("Unobtainium") && e.contains("Au"), "{e}");
}

/// A heterogeneous medium exists only inside its σ_t volume's box, a
/// `constvolume`'s too: the unit cube under its `to_world` (Mitsuba's
/// `Volume::bbox`), clipped to the shape that bounds it.
#[test]
fn constant_volumes_bound_heterogeneous_media() {
    let v = scene_xml(
        "<integrator type=\"volpath\"/><medium type=\"heterogeneous\" id=\"m\"><volume type=\"constvolume\" name=\"sigma_t\">\
         <rgb name=\"value\" value=\"0.5\"/><transform name=\"to_world\"><translate x=\"-0.5\" y=\"-0.5\" z=\"-0.5\"/></transform>\
         </volume></medium><shape type=\"cube\"><transform name=\"to_world\"><scale value=\"0.75\"/></transform>\
         <bsdf type=\"null\"/><ref name=\"interior\" id=\"m\"/></shape>",
    );
    // A box of edge 1 centred at the origin, not the cube's 1.5.
    let m = &v["media"][0]["to_world"]["matrix"];
    let diag: Vec<f64> = (0..3).map(|i| m[i][i].as_float().unwrap()).collect();
    assert!(diag.iter().all(|d| (d - 1.0).abs() < 1e-6), "{m:?}");
}

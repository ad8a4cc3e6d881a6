//! Shape groups placed by instances (`group`, `type = "instance"`; pbrt-v4's
//! `ObjectInstance`, Mitsuba 3's `shapegroup`/`instance`): a scene whose
//! groups are instanced answers every ray as the same scene with each
//! instance's shapes copied under the composed transforms (same distance,
//! point, normals, UVs and material), including mirroring and non-uniform
//! placements; the two render the same
//! image (per-pixel z-test); bad instances are refused naming the key; and
//! the pbrt-v4 and Mitsuba 3 readers keep instancing as instancing.

use fogbank_math::{DAffine3, DVec3, Pcg32, Ray, Vec3};
use fogbank_render::render::{render, Progress, RenderOptions};
use fogbank_render::world::surfaces::{SurfaceHit, Surfaces};
use fogbank_render::{parse_scene, Scene};
use glam::DQuat;
use std::path::Path;

const HEAD: &str = "[camera]\nfrom = [0.0, 1.0, 9.0]\nto = [0.0, 0.0, 0.0]\nfov = 50.0\n\
    width = 24\nheight = 16\n\
    [[lights]]\ntype = \"constant\"\nradiance = [0.6, 0.7, 0.9]\n\
    [[lights]]\ntype = \"point\"\nposition = [1.0, 4.0, 3.0]\nintensity = [20.0, 20.0, 20.0]\n\
    [integrator]\ntype = \"volpath\"\nmax_depth = 5\n";

fn matrix(m: DAffine3) -> String {
    let c = glam::DMat4::from(m).transpose().to_cols_array_2d();
    let rows: Vec<String> = c
        .iter()
        .map(|r| format!("[{}, {}, {}, {}]", r[0], r[1], r[2], r[3]))
        .collect();
    format!("{{ matrix = [{}] }}", rows.join(", "))
}

/// A group member: type, extra keys and its placement in the group.
struct Member {
    kind: &'static str,
    keys: &'static str,
    to_group: DAffine3,
}

fn members() -> Vec<(&'static str, Member)> {
    let t = |x: f64, y: f64, z: f64| DAffine3::from_translation(DVec3::new(x, y, z));
    vec![
        (
            "block",
            Member {
                kind: "cube",
                keys: "bsdf = { type = \"diffuse\", reflectance = [0.8, 0.3, 0.2] }\n",
                to_group: DAffine3::from_scale(DVec3::new(0.5, 0.3, 0.4)),
            },
        ),
        (
            "block",
            Member {
                kind: "rectangle",
                keys: "bsdf = { type = \"null\" }\n",
                to_group: t(0.0, 0.6, 0.0),
            },
        ),
        (
            "block",
            Member {
                kind: "disk",
                keys: "bsdf = { type = \"conductor\" }\n",
                to_group: t(0.0, 0.0, 0.7) * DAffine3::from_scale(DVec3::splat(0.3)),
            },
        ),
        (
            "ball",
            Member {
                kind: "sphere",
                keys: "bsdf = { type = \"diffuse\", reflectance = [0.2, 0.7, 0.3] }\n",
                to_group: t(0.2, 0.0, 0.0) * DAffine3::from_scale(DVec3::splat(0.4)),
            },
        ),
    ]
}

/// Placements: blocks turned, stretched and one mirrored; balls scaled
/// uniformly.
fn instances() -> Vec<(&'static str, DAffine3)> {
    let q =
        |x: f64, y: f64, z: f64, a: f64| DQuat::from_axis_angle(DVec3::new(x, y, z).normalize(), a);
    let place = |s: DVec3, r: DQuat, t: DVec3| DAffine3::from_scale_rotation_translation(s, r, t);
    vec![
        ("block", DAffine3::IDENTITY),
        (
            "block",
            place(
                DVec3::new(1.5, 0.7, 1.0),
                q(1.0, 1.0, 0.0, 0.7),
                DVec3::new(-2.0, 0.5, 0.0),
            ),
        ),
        (
            "block",
            place(
                DVec3::new(-1.0, 1.2, 1.0),
                q(0.0, 1.0, 0.3, 2.0),
                DVec3::new(2.0, -0.5, 1.0),
            ),
        ),
        (
            "ball",
            place(
                DVec3::splat(1.3),
                q(0.0, 0.0, 1.0, 0.4),
                DVec3::new(0.0, 1.5, -1.0),
            ),
        ),
        (
            "ball",
            place(
                DVec3::splat(0.6),
                q(1.0, 0.0, 0.0, 1.0),
                DVec3::new(-1.5, -1.2, 1.5),
            ),
        ),
        (
            "block",
            place(
                DVec3::new(0.8, 0.8, 2.0),
                q(1.0, 0.0, 1.0, 2.5),
                DVec3::new(1.0, 1.8, -2.0),
            ),
        ),
    ]
}

const FLOOR: &str = "[[shapes]]\ntype = \"rectangle\"\n\
    to_world = { translate = [0.0, -2.5, 0.0], rotate = [1.0, 0.0, 0.0, -90.0], scale = 6.0 }\n";

/// The scene with groups and instances (`instanced`) or with copies.
fn scene_text(instanced: bool) -> String {
    let mut s = format!("{HEAD}{FLOOR}");
    if instanced {
        for (g, m) in members() {
            s += &format!(
                "[[shapes]]\ntype = \"{}\"\ngroup = \"{g}\"\nto_world = {}\n{}",
                m.kind,
                matrix(m.to_group),
                m.keys
            );
        }
        for (g, place) in instances() {
            s += &format!(
                "[[shapes]]\ntype = \"instance\"\ngroup = \"{g}\"\nto_world = {}\n",
                matrix(place)
            );
        }
    } else {
        for (g, place) in instances() {
            for (mg, m) in members().into_iter().filter(|(mg, _)| *mg == g) {
                let _ = mg;
                s += &format!(
                    "[[shapes]]\ntype = \"{}\"\nto_world = {}\n{}",
                    m.kind,
                    matrix(place * m.to_group),
                    m.keys
                );
            }
        }
    }
    s
}

fn build(text: &str) -> Result<Scene, String> {
    let desc = parse_scene(text, "test", &[]).map_err(|e| e.to_string())?;
    Scene::build(desc, Path::new(".")).map_err(|e| e.to_string())
}

fn surfaces(s: &Scene) -> &Surfaces {
    s.world.surfaces.as_ref().unwrap()
}

/// Whether two hits are the same point of the same material.
fn same_hit(a: &SurfaceHit, sa: &Surfaces, b: &SurfaceHit, sb: &Surfaces) -> bool {
    let material =
        |h: &SurfaceHit, s: &Surfaces| format!("{:?}", s.shapes[h.shape as usize].material);
    (a.t - b.t).abs() <= 1e-4 * b.t.max(1.0)
        && (a.p - b.p).length() <= 1e-4 * (1.0 + b.p.length())
        && a.ng.dot(b.ng) > 0.9999
        && a.ns.dot(b.ns) > 0.999
        && (a.uv - b.uv).length() < 1e-3
        && material(a, sa) == material(b, sb)
}

/// Random rays from around the scene toward points in its box: every
/// query of `a` answers as `b`'s but for grazing rays (≤ 0.2 %), and a
/// good share of rays hit.
fn assert_same_answers(a: &Surfaces, b: &Surfaces, what: &str) {
    let mut rng = Pcg32::new(5, 9);
    let n = 20_000;
    let (mut hits, mut differ) = (0, 0);
    let bounds = b.bounds();
    let (centre, half) = (
        (bounds.min + bounds.max) / 2.0,
        (bounds.max - bounds.min) / 2.0,
    );
    for _ in 0..n {
        let mut r = || 2.0 * rng.next_f32() - 1.0;
        let o = centre + Vec3::new(r(), r(), r()) * half * 2.0;
        let d = centre + Vec3::new(r(), r(), r()) * half - o;
        let ray = Ray::new(o, d);
        let (ha, hb) = (
            a.intersect(&ray, f32::INFINITY),
            b.intersect(&ray, f32::INFINITY),
        );
        let (oa, ob) = (
            a.intersect_opaque(&ray, f32::INFINITY),
            b.intersect_opaque(&ray, f32::INFINITY),
        );
        let same = |x: Option<SurfaceHit>, y: Option<SurfaceHit>| match (x, y) {
            (None, None) => true,
            (Some(x), Some(y)) => same_hit(&x, a, &y, b),
            _ => false,
        };
        let t_occ = hb.map_or(3.0, |h| h.t * 1.5);
        let agree = same(ha, hb)
            && same(oa, ob)
            && a.occluded(&ray, t_occ) == b.occluded(&ray, t_occ)
            && a.occluded(&ray, f32::INFINITY) == b.occluded(&ray, f32::INFINITY);
        hits += hb.is_some() as u32;
        differ += !agree as u32;
    }
    assert!(hits > n / 5, "{what}: {hits} of {n} rays hit");
    assert!(
        differ * 500 <= n,
        "{what}: {differ} of {n} rays answered differently"
    );
}

#[test]
fn instances_answer_rays_as_copies_do() {
    let inst = build(&scene_text(true)).unwrap();
    let copies = build(&scene_text(false)).unwrap();
    let (si, sc) = (surfaces(&inst), surfaces(&copies));
    assert_same_answers(si, sc, "instances vs copies");
    // Group members are shapes once, however often placed.
    assert_eq!(si.shapes.len(), 1 + members().len());
    assert_eq!(sc.shapes.len(), 1 + 4 * 3 + 2);
    // Bounds take the instances in.
    let (bi, bc) = (si.bounds(), sc.bounds());
    assert!(
        (bi.min - bc.min).abs().max_element() < 0.3 && (bi.max - bc.max).abs().max_element() < 0.3
    );
    assert!(
        bi.min.cmple(bc.min).all() && bi.max.cmpge(bc.max).all(),
        "{bi:?} {bc:?}"
    );
}

#[test]
fn instances_render_as_copies_do() {
    let inst = build(&scene_text(true)).unwrap();
    let copies = build(&scene_text(false)).unwrap();
    let opts = RenderOptions::new(48, 3);
    let a = render(&inst, &opts, &Progress::default()).film;
    let b = render(&copies, &opts, &Progress::default()).film;
    let (ma, va, mb, vb) = (
        a.mean(),
        a.variance_of_mean(),
        b.mean(),
        b.variance_of_mean(),
    );
    let mut worst: f32 = 0.0;
    for i in 0..ma.len() {
        for c in 0..3 {
            let diff = (ma[i][c] - mb[i][c]).abs();
            let sd = (va[i][c] + vb[i][c]).sqrt();
            let z = if sd > 0.0 { diff / sd } else { diff * 1e4 };
            worst = worst.max(z);
        }
    }
    assert!(worst < 5.0, "largest per-pixel |z| {worst}");
    // Not a vacuous image: the instances are in view.
    let lit = ma.iter().zip(&mb).filter(|(x, _)| x[0] > 0.01).count();
    assert!(lit > ma.len() / 2, "{lit} pixels");
}

#[test]
fn bad_instances_are_refused_naming_the_key() {
    let base = format!(
        "{HEAD}[[shapes]]\ntype = \"cube\"\ngroup = \"g\"\n[[shapes]]\ntype = \"sphere\"\ngroup = \"s\"\n"
    );
    let cases = [
        ("[[shapes]]\ntype = \"instance\"\n", "shapes.2: an instance needs `group`"),
        (
            "[[shapes]]\ntype = \"instance\"\ngroup = \"g\"\nbsdf = { type = \"diffuse\" }\n",
            "shapes.2.bsdf: an instance takes only",
        ),
        ("[[shapes]]\ntype = \"instance\"\ngroup = \"h\"\n", "shapes.2.group: no shape has group \"h\""),
        (
            "[[shapes]]\ntype = \"instance\"\ngroup = \"s\"\nto_world = { scale = [1.0, 2.0, 1.0] }\n",
            "shapes.2.to_world: group \"s\" holds a sphere",
        ),
        (
            "[[shapes]]\ntype = \"instance\"\ngroup = \"g\"\nto_world = { scale = [1.0, 0.0, 1.0] }\n",
            "shapes.2.to_world: not invertible",
        ),
        (
            "[[shapes]]\ntype = \"rectangle\"\ngroup = \"g\"\nemitter = { radiance = [1.0, 1.0, 1.0] }\n",
            "shapes.2.emitter: a shape of a group (instanced) cannot emit",
        ),
    ];
    for (extra, want) in cases {
        let e = build(&format!("{base}{extra}")).err().unwrap_or_default();
        assert!(e.contains(want), "{extra}: {e}");
    }
    // A group without instances is drawn nowhere.
    let s = build(&base).unwrap();
    assert!(surfaces(&s)
        .intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z), 100.0)
        .is_none());
}

/// pbrt-v4's ObjectInstance and Mitsuba 3's shapegroup/instance read as
/// groups and instances, and answer rays as the copies written out do.
#[test]
fn pbrt_and_mitsuba_instancing_stays_instancing() {
    let head = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
        Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n";
    let object = "ObjectBegin \"o\"\nShape \"sphere\" \"float radius\" 0.25\nTranslate 0 0.5 0\n\
        Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2]\nObjectEnd\n";
    let places = [
        "Translate 1 0 0",
        "Rotate 30 0 0 1 Translate -1 0 0",
        "Scale 0.5 0.5 0.5",
    ];
    let mut inst = format!("{head}{object}");
    let mut copies = head.to_string();
    for p in places {
        inst += &format!("AttributeBegin\n{p}\nObjectInstance \"o\"\nAttributeEnd\n");
        copies += &format!(
            "AttributeBegin\n{p}\nShape \"sphere\" \"float radius\" 0.25\nTranslate 0 0.5 0\n\
             Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2]\nAttributeEnd\n"
        );
    }
    let pbrt = |text: &str| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/pbrt/t.pbrt");
        let t = fogbank_scene::pbrt::load_pbrt_str(text, &path).unwrap_or_else(|e| panic!("{e}"));
        let d = parse_scene(&toml::to_string(&t).unwrap(), "t.pbrt", &[]).unwrap();
        (d.clone(), Scene::build(d, Path::new(".")).unwrap())
    };
    let (di, si) = pbrt(&inst);
    let (_, sc) = pbrt(&copies);
    let kinds: Vec<String> = di
        .shapes
        .iter()
        .map(|s| format!("{:?}{:?}", s.kind, s.group))
        .collect();
    assert_eq!(kinds.len(), 5, "{kinds:?}");
    assert_eq!(
        kinds.iter().filter(|k| k.starts_with("Instance")).count(),
        3,
        "{kinds:?}"
    );
    assert_same_answers(
        surfaces(&si),
        surfaces(&sc),
        "pbrt ObjectInstance vs copies",
    );

    let xml = |body: &str| {
        format!(
            "<scene version=\"3.0.0\"><sensor type=\"perspective\"><transform name=\"to_world\">\
             <lookat origin=\"0,0,5\" target=\"0,0,0\" up=\"0,1,0\"/></transform>\
             <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/><rfilter type=\"box\"/></film>\
             </sensor><emitter type=\"constant\"/>{body}</scene>"
        )
    };
    let ball = "<shape type=\"sphere\"><float name=\"radius\" value=\"0.3\"/></shape>\
        <shape type=\"cube\"><transform name=\"to_world\"><scale value=\"0.2\"/><translate y=\"0.6\"/></transform></shape>";
    let places = [
        "<translate x=\"1\"/>",
        "<rotate z=\"1\" angle=\"40\"/><translate x=\"-1\"/>",
    ];
    let mut inst = format!("<shape type=\"shapegroup\" id=\"g\">{ball}</shape>");
    let mut copies = String::new();
    for p in places {
        inst += &format!(
            "<shape type=\"instance\"><ref id=\"g\"/><transform name=\"to_world\">{p}</transform></shape>"
        );
        copies += &format!(
            "<shape type=\"sphere\"><float name=\"radius\" value=\"0.3\"/><transform name=\"to_world\">{p}</transform></shape>\
             <shape type=\"cube\"><transform name=\"to_world\"><scale value=\"0.2\"/><translate y=\"0.6\"/>{p}</transform></shape>"
        );
    }
    let mitsuba = |text: &str| {
        let t = fogbank_scene::mitsuba::load_xml_str(text, Path::new("t.xml"), &[])
            .unwrap_or_else(|e| panic!("{e}"));
        let d = parse_scene(&toml::to_string(&t).unwrap(), "t.xml", &[]).unwrap();
        (d.clone(), Scene::build(d, Path::new(".")).unwrap())
    };
    let (di, si) = mitsuba(&xml(&inst));
    let (_, sc) = mitsuba(&xml(&copies));
    assert_eq!(di.shapes.len(), 4);
    assert_same_answers(surfaces(&si), surfaces(&sc), "Mitsuba instance vs copies");
    // Mitsuba refuses emitters in shape groups; so does the reader.
    let bad = "<shape type=\"shapegroup\" id=\"g\"><shape type=\"sphere\"><emitter type=\"area\"/></shape></shape>\
        <shape type=\"instance\"><ref id=\"g\"/></shape>";
    let e = fogbank_scene::mitsuba::load_xml_str(&xml(bad), Path::new("t.xml"), &[]).unwrap_err();
    assert!(e.0.contains("cannot emit"), "{e}");
}

/// Written as Mitsuba XML (`shapegroup`s first, then `instance`s) and read
/// back, the instanced scene still answers as the copies.
#[test]
fn instances_survive_the_mitsuba_writer() {
    let dir = std::env::temp_dir().join(format!("fogbank-instances-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (toml_path, xml_path) = (dir.join("inst.toml"), dir.join("inst.xml"));
    std::fs::write(&toml_path, scene_text(true)).unwrap();
    fogbank_scene::convert::mitsuba_writer::convert(&toml_path, &xml_path).unwrap();
    let xml = std::fs::read_to_string(&xml_path).unwrap();
    assert_eq!(xml.matches("type=\"shapegroup\"").count(), 2, "{xml}");
    assert_eq!(xml.matches("type=\"instance\"").count(), instances().len());
    let back = fogbank_scene::load_scene(Some(&xml_path), &[]).unwrap();
    let copies = build(&scene_text(false)).unwrap();
    assert_same_answers(surfaces(&back), surfaces(&copies), "written and read back");
    let _ = std::fs::remove_dir_all(&dir);
}

//! The pin stream (Hansen 2025 §3.4.4, §3.7; `shared::pin_stream`): a stream
//! rewrites some cells reproducibly, and a render's stream gives pass s the
//! gathered grids after the streams of passes 0..=s.

use fogbank_render::integrators::shared::pin_stream::{stream, STREAM_SPACING};
use fogbank_render::integrators::shared::tracking::PinSet;
use fogbank_render::integrators::volpath::VolPath;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, Scene};

fn scene(text: &str) -> Scene {
    Scene::build(
        parse_scene(text, "t", &[]).unwrap(),
        std::path::Path::new("."),
    )
    .unwrap()
}

fn volpath(s: &Scene) -> &VolPath {
    let IntegratorKind::VolPath(v) = &s.integrator else {
        panic!("volpath");
    };
    v
}

/// Streaming rewrites some cells and keeps the rest, deterministically
/// for a given random stream, and leaves the input set as it was.
#[test]
fn a_stream_rewrites_some_cells_reproducibly() {
    let text = "[camera]\nwidth = 4\nheight = 4\n\
        [[media]]\ndensity = { procedural = \"cloud\", resolution = 16 }\nsigma_t_scale = 10.0\n\
        [integrator]\ntype = \"volpath\"\npins = \"all\"\npin_grid = { positions = 4 }\n";
    let s = scene(text);
    let v = volpath(&s);
    let set = v.pin_set(&s.world).unwrap().clone();
    let before = set.media[0].as_ref().unwrap().pins.clone();
    let a = stream(&set, &s.world, 50, STREAM_SPACING, 3, 1);
    let b = stream(&set, &s.world, 50, STREAM_SPACING, 3, 1);
    let (pa, pb) = (
        &a.media[0].as_ref().unwrap().pins,
        &b.media[0].as_ref().unwrap().pins,
    );
    assert_eq!(pa, pb, "the same stream gives the same grid");
    assert_eq!(set.media[0].as_ref().unwrap().pins, before, "input kept");
    let changed = pa.iter().zip(&before).filter(|(x, y)| x != y).count();
    assert!(
        changed > 0 && changed < before.len(),
        "{changed} of {} cells",
        before.len()
    );
    let other = stream(&set, &s.world, 50, STREAM_SPACING, 3, 2);
    assert_ne!(&other.media[0].as_ref().unwrap().pins, pa, "another pass");
}

/// A render's stream gives pass s the gathered grids after the streams
/// of passes 0..=s, however the passes are asked for (in order, again,
/// or from an earlier pass: a replay).
#[test]
fn each_pass_sees_the_streams_up_to_it() {
    let text = "[camera]\nwidth = 4\nheight = 4\n\
        [[media]]\ndensity = { procedural = \"cloud\", resolution = 16 }\nsigma_t_scale = 10.0\n\
        [integrator]\ntype = \"volpath\"\npins = \"ms\"\n\
        pin_grid = { positions = 4, stream = 30, seed = 9 }\n";
    let s = scene(text);
    let v = volpath(&s);
    let pins = |set: &PinSet| set.media[0].as_ref().unwrap().pins.clone();
    let mut by_hand = vec![v.pin_set(&s.world).unwrap().clone()];
    for pass in 0..4 {
        let next = stream(
            by_hand.last().unwrap(),
            &s.world,
            30,
            STREAM_SPACING,
            9,
            pass,
        );
        by_hand.push(next);
    }
    let mut st = v.pin_stream(&s.world).expect("stream on");
    for pass in [0, 1, 1, 3, 2, 0, 3] {
        let got = pins(st.at(&s.world, pass));
        assert_eq!(got, pins(&by_hand[pass as usize + 1]), "pass {pass}");
    }
    let off = |k: &str| {
        let t = text.replace("stream = 30", k);
        let s = scene(&t);
        volpath(&s).pin_stream(&s.world).is_none()
    };
    assert!(!off("stream = 30"));
    assert!(off("stream = 0") && off("stream = 30, unquantised = true"));
}

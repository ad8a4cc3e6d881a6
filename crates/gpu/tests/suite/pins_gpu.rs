//! Hansen 2025 on the GPU against the CPU reference (lavapipe in CI): the pin
//! grid gathered in a compute pass is the CPU's grid (same cells, same
//! streams; only rounding of the marched transmittances may flip a bit),
//! and `volpath` with ray marching and pins agrees with the CPU per pixel
//! (z-test) at equal spp with matching lookup counts, for every pin mode,
//! unquantised pins, the render-time pin stream and instances sharing one
//! grid.

use fogbank_gpu::pins::{gathered_pins, streamed_pins};
use fogbank_gpu::test_gpu;
use fogbank_render::integrators::volpath::VolPath;
use fogbank_render::integrators::IntegratorKind;
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

use crate::support;
use support::assert_gpu_matches_cpu;

const LIGHTS: &str = "[[lights]]\ntype = \"constant\"\nradiance = [0.3, 0.4, 0.5]\n\
    [[lights]]\ntype = \"point\"\nposition = [0.05, 0.1, 0.0]\nintensity = [0.3, 0.3, 0.2]\n\
    [[lights]]\ntype = \"directional\"\ndirection = [-0.3, -1.0, -0.2]\nirradiance = [1.5, 1.4, 1.2]\n";

/// Two overlapping clouds (trilinear and stochastic filters) under three
/// lights, `volpath` with `extra` overrides.
fn scene(extra: &[&str]) -> Scene {
    let text = format!(
        "[camera]\nwidth = 20\nheight = 16\nfov = 30.0\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 32, seed = 5 }}\nsigma_t_scale = 12.0\n\
         albedo = [0.9, 0.8, 0.7]\nphase = {{ type = \"hg\", g = 0.4 }}\nfilter = \"trilinear\"\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 16, seed = 9 }}\nsigma_t_scale = 5.0\n\
         albedo = [0.6, 0.7, 0.9]\nphase = {{ type = \"hg\", g = -0.3 }}\nfilter = \"stochastic_trilinear\"\n\
         to_world = {{ translate = [0.2, 0.1, 0.1], scale = 0.6 }}\n\
         {LIGHTS}\n[integrator]\ntype = \"volpath\"\nmax_depth = 6\n"
    );
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    Scene::build(parse_scene(&text, "test", &extra).unwrap(), &base).unwrap()
}

/// [`scene`] with PinMS on a small 5³ × 8 × 3 grid (and `extra`), whose
/// grids the gather and stream tests read back.
fn grid_scene(extra: &[&str]) -> Scene {
    let mut set = vec![
        "integrator.pins=ms",
        "integrator.pin_grid.positions=5",
        "integrator.pin_grid.phi=8",
        "integrator.pin_grid.theta=3",
    ];
    set.extend_from_slice(extra);
    scene(&set)
}

fn volpath(s: &Scene) -> &VolPath {
    let IntegratorKind::VolPath(v) = &s.integrator else {
        panic!("volpath")
    };
    v
}

fn compare(extra: &[&str], spp: u32) {
    let Some(gpu) = test_gpu() else { return };
    assert_gpu_matches_cpu(&gpu, &scene(extra), spp, 0.01, &format!("{extra:?}"));
}

/// The gather kernel reproduces the CPU's `PinGrid::gather`: the same pin
/// in (almost) every cell — a bit may flip where a Bernoulli draw lands
/// within rounding of (1 − t_i)/(1 − t_min) — and t_min to float rounding.
#[test]
fn the_gathered_grid_is_the_cpus() {
    let Some(gpu) = test_gpu() else { return };
    let s = grid_scene(&[]);
    let v = volpath(&s);
    let cpu = v.pin_set(&s.world).unwrap();
    let gpu_grids = gathered_pins(&gpu, &s).unwrap();
    assert_eq!(gpu_grids.len(), 2, "one grid per (non-instanced) medium");
    for (mi, pins) in gpu_grids {
        let grid = cpu.media[mi].as_ref().unwrap();
        assert_eq!(pins.len(), grid.pins.len());
        assert_eq!(pins.len(), 125 * 24);
        let mut same_mask = 0;
        let mut worst_t = 0.0f32;
        let mut attenuating = 0;
        for (g, c) in pins.iter().zip(&grid.pins) {
            same_mask += (g[0] == c.mask) as usize;
            worst_t = worst_t.max((f32::from_bits(g[1]) - c.t_min).abs());
            attenuating += (c.t_min < 0.99) as usize;
        }
        let n = pins.len();
        assert!(
            same_mask as f64 >= 0.99 * n as f64,
            "medium {mi}: {same_mask} of {n} masks identical"
        );
        assert!(worst_t < 1e-3, "medium {mi}: t_min differs by {worst_t}");
        assert!(
            attenuating > n / 4,
            "medium {mi}: the pins must see the medium"
        );
        eprintln!("medium {mi}: {same_mask}/{n} masks identical, max |Δt_min| {worst_t:.2e}");
    }
}

/// The stream kernel writes the CPU's stream pins (`pin_grid.stream`):
/// after two passes the grids match the CPU's streamed grids cell for cell
/// as the gathered ones do — a cell two pins of one pass cross may keep
/// the other pin (the tolerated write race) — and the stream did rewrite
/// cells.
#[test]
fn the_streamed_grid_is_the_cpus() {
    let Some(gpu) = test_gpu() else { return };
    let s = grid_scene(&[
        "integrator.pin_grid.stream=60",
        "integrator.pin_grid.stream_spacing=0.2",
    ]);
    let v = volpath(&s);
    let gathered = v.pin_set(&s.world).unwrap().clone();
    let mut stream = v.pin_stream(&s.world).unwrap();
    let cpu = stream.at(&s.world, 1).clone();
    let gpu_grids = streamed_pins(&gpu, &s, 2).unwrap();
    assert_eq!(gpu_grids.len(), 2);
    for (mi, pins) in gpu_grids {
        let (before, after) = (
            &gathered.media[mi].as_ref().unwrap().pins,
            &cpu.media[mi].as_ref().unwrap().pins,
        );
        let rewritten: Vec<usize> = (0..after.len())
            .filter(|&i| after[i] != before[i])
            .collect();
        let same = pins
            .iter()
            .zip(after)
            .filter(|(g, c)| g[0] == c.mask && (f32::from_bits(g[1]) - c.t_min).abs() < 1e-3)
            .count();
        let same_rewritten = rewritten
            .iter()
            .filter(|&&i| pins[i][0] == after[i].mask)
            .count();
        let n = pins.len();
        eprintln!(
            "medium {mi}: {same}/{n} pins identical; {same_rewritten}/{} streamed cells",
            rewritten.len()
        );
        assert!(rewritten.len() > 50, "medium {mi}: the stream must write");
        assert!(same as f64 >= 0.99 * n as f64, "medium {mi}: {same} of {n}");
        assert!(
            same_rewritten as f64 >= 0.95 * rewritten.len() as f64,
            "medium {mi}: {same_rewritten} of {} streamed cells",
            rewritten.len()
        );
    }
}

/// PinMS with the render-time stream (the grids change before every pass,
/// one sample index a dispatch on the GPU) agrees with the CPU.
#[test]
fn streamed_pins_match_the_cpu() {
    compare(
        &[
            "integrator.pins=ms",
            "integrator.pin_grid.positions=6",
            "integrator.pin_grid.stream=100",
        ],
        256,
    );
}

/// Hansen 2025's baseline: fixed-step ray marching for every ray.
#[test]
fn ray_marching_matches_the_cpu() {
    compare(
        &[
            "integrator.tracking=ray_marching",
            "integrator.march_step=0.05",
        ],
        256,
    );
}

/// PinMS (the thesis's method), pins for every ray, and pins after the
/// view ray with unquantised pins (traced along each query).
#[test]
fn pins_match_the_cpu_in_every_mode() {
    compare(
        &["integrator.pins=ms", "integrator.pin_grid.positions=6"],
        256,
    );

    compare(
        &[
            "integrator.pins=all",
            "integrator.pin_grid.positions=4",
            "integrator.pin_grid.mask_iterations=3",
        ],
        256,
    );
    // Single scattering with pins on every ray: the least blurred case,
    // where a wrong bit order or mask density shows most.
    compare(
        &[
            "integrator.pins=all",
            "integrator.max_depth=1",
            "integrator.pin_grid.positions=8",
            "integrator.pin_grid.jitter=0",
        ],
        512,
    );
    compare(
        &[
            "integrator.pins=secondary",
            "integrator.tracking=unbiased",
            "integrator.pin_grid.unquantised=true",
            "integrator.pin_grid.step=0.04",
        ],
        128,
    );
}

/// PinMS with surfaces: a cloud over a diffuse ground
/// lit by an area light and the sky — ray-marched NEE at the first vertex,
/// surface or medium, pins from vertex 2 on, surface shadows through the
/// pinned medium — agrees with the CPU.
#[test]
fn pins_with_surfaces_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let text = "[camera]\nfrom = [0.0, 0.3, 1.6]\nto = [0.0, -0.1, 0.0]\nwidth = 20\nheight = 16\nfov = 40.0\n\
        [[media]]\ndensity = { procedural = \"cloud\", resolution = 32, seed = 5 }\nsigma_t_scale = 12.0\n\
        albedo = [0.9, 0.8, 0.7]\nphase = { type = \"hg\", g = 0.4 }\n\
        [[shapes]]\ntype = \"rectangle\"\n\
        to_world = { translate = [0.0, -0.5, 0.0], rotate = [1.0, 0.0, 0.0, -90.0], scale = 2.0 }\n\
        bsdf = { type = \"diffuse\", reflectance = [0.6, 0.55, 0.5] }\n\
        [[shapes]]\ntype = \"rectangle\"\n\
        to_world = { translate = [-0.3, 1.2, 0.2], rotate = [1.0, 0.0, 0.0, 90.0], scale = 0.3 }\n\
        emitter = { radiance = [6.0, 5.5, 5.0] }\n\
        [[lights]]\ntype = \"constant\"\nradiance = [0.1, 0.12, 0.15]\n\
        [integrator]\ntype = \"volpath\"\nmax_depth = 5\npins = \"ms\"\n";
    // One configuration: lavapipe compiles the kernel with pins and
    // surfaces for about a minute.
    let set = vec!["integrator.pin_grid.positions=6".to_string()];
    let s = Scene::build(parse_scene(text, "test", &set).unwrap(), Path::new(".")).unwrap();
    assert!(s.world.surfaces.is_some());
    assert_gpu_matches_cpu(&gpu, &s, 128, 0.01, "PinMS with surfaces");
}

/// Rigid instances share one grid (gathered once) on the GPU too.
#[test]
fn instanced_pins_match_the_cpu() {
    let instances = "media.1.instances=[{ translate = [0.0, 0.0, 0.0] }, \
        { translate = [-0.35, 0.05, 0.1], rotate = [0.0, 1.0, 0.0, 30.0] }]";
    if let Some(gpu) = test_gpu() {
        let s = scene(&[
            "integrator.pins=ms",
            "integrator.pin_grid.positions=4",
            instances,
        ]);
        let grids = gathered_pins(&gpu, &s).unwrap();
        assert_eq!(
            grids.iter().map(|g| g.0).collect::<Vec<_>>(),
            [0, 1],
            "the second instance reads the first's grid"
        );
    }
    compare(
        &[
            "integrator.pins=ms",
            "integrator.pin_grid.positions=4",
            instances,
        ],
        128,
    );
}

/// pins.wgsl query by query against `Chord` (same f32 inputs): the
/// popcount exponent, MSB distance sampling, the majorant-masked distance
/// from the same stream and T̃, on random and adversarial rays (inside and
/// outside the cube, against +z, in the z = const plane, empty and full
/// masks, t_min 0 and 1, segments ending inside and past the exit).
#[test]
fn pin_queries_match_the_cpu_query_by_query() {
    use fogbank_estimators::pins::{Chord, Pin};
    use fogbank_gpu::diagnostics::{chord_queries, ChordQuery};
    use fogbank_math::{Pcg32, Ray, Vec3};
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::new(11, 3);
    let mut queries = Vec::new();
    for i in 0..4000u32 {
        let mut f = || rng.next_f32();
        let o = [f() * 1.6 - 0.3, f() * 1.6 - 0.3, f() * 1.6 - 0.3];
        let mut d = [f() - 0.5, f() - 0.5, f() - 0.5];
        if i % 7 == 0 {
            d[2] = 0.0;
        }
        if i % 11 == 0 {
            d = [0.0, 0.0, -1.0];
        }
        let mask = match i % 5 {
            0 => 0,
            1 => u32::MAX,
            _ => rng.next_u32(),
        };
        let t_min = match i % 6 {
            0 => 0.0,
            1 => 1.0,
            _ => rng.next_f32(),
        };
        let mut f = || rng.next_f32();
        queries.push(ChordQuery {
            o,
            t_start: f() * 0.8,
            d,
            max_len: if i % 3 == 0 { 1e6 } else { f() * 1.5 },
            mask,
            t_min,
            u: f(),
            iterations: 1 + i % 6,
        });
    }
    let answers = chord_queries(&gpu, &queries).unwrap();
    let (mut differing, mut hits, mut valid) = (0, 0, 0);
    for (i, (q, a)) in queries.iter().zip(&answers).enumerate() {
        let ray = Ray::new(Vec3::from(q.o), Vec3::from(q.d));
        let Some(c) = Chord::new(&ray, q.t_start) else {
            differing += (a[0] != u32::MAX) as usize;
            continue;
        };
        valid += 1;
        let pin = Pin {
            mask: q.mask,
            t_min: q.t_min,
        };
        let mut r = Pcg32::new(i as u64, 7);
        let expect = [
            c.count(q.mask, q.max_len),
            c.sample_distance(q.mask, q.max_len, q.u)
                .unwrap_or(-1.0)
                .to_bits(),
            c.distance(&pin, q.max_len, q.iterations, &mut r)
                .unwrap_or(-1.0)
                .to_bits(),
            c.transmittance(&pin, q.max_len).to_bits(),
        ];
        hits += (expect[2] != (-1.0f32).to_bits()) as usize;
        let close = |x: u32, y: u32| {
            let (x, y) = (f32::from_bits(x), f32::from_bits(y));
            (x - y).abs() <= 1e-5 * x.abs().max(1.0)
        };
        let same = a[0] == expect[0] && (1..4).all(|k| close(a[k], expect[k]));
        differing += !same as usize;
    }
    // Rounding of the chord's ends may move a query across a bit boundary.
    assert!(
        differing * 500 <= queries.len(),
        "{differing} of {} queries differ",
        queries.len()
    );
    assert!(valid > 1000 && hits > 300, "valid {valid}, hits {hits}");
    eprintln!(
        "{differing} of {} queries differ ({valid} valid, {hits} collisions)",
        queries.len()
    );
}

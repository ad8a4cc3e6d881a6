//! GPU `restir` against the CPU (Lin et al. 2021): the mean of
//! the last frame of independent sequences agrees per pixel (z-test) with
//! the CPU's for the configurations of the CPU's unbiasedness test
//! (`eval/tests/restir_unbiased_test.rs`): the environment-lit and the
//! point-lit (HG g = 0.7) test volume, the emissive explosion and the
//! volume among reflecting and emitting shapes at K = 1 and 3, no reuse, vertex reuse, a BC4 reuse mip and a moving light; and
//! the test has the power to reject the GPU with plain 1/M weights against
//! the CPU with Talbot MIS. Lavapipe in CI.

use fogbank_gpu::restir::last_frames;
use fogbank_gpu::{render as gpu_render, test_gpu, Gpu};
use fogbank_image::metrics::ztest::{ztest, ZTest};
use fogbank_math::testdata::checker_slab_raw;
use fogbank_render::{parse_scene, render, Film, Progress, RenderOptions, Scene};
use std::path::Path;

use crate::support;
use support::image;

/// Independent sequences per image, on each device (lavapipe runs the
/// kernels on the CI machine's two cores: 64 keep this file near a minute
/// and a half, and still reject 1/M weights).
const SEQUENCES: u32 = 64;

const ENV: &str = "[[lights]]\ntype = \"constant\"\nradiance = [0.8, 0.9, 1.0]\n";
const POINT: &str =
    "[[lights]]\ntype = \"point\"\nposition = [0.6, 0.7, 0.5]\nintensity = [1.5, 1.4, 1.2]\n";

fn slab(lights: &str, medium_extra: &str) -> String {
    let raw = checker_slab_raw("fogbank_restir_gpu_test");
    format!(
        "[camera]\nfrom = [0.0, 0.0, 1.4]\nwidth = 16\nheight = 12\nfov = 25.0\n\
         [[media]]\ndensity = {{ raw = \"{raw}\", dims = [24, 24, 24], type = \"f32\" }}\n\
         sigma_t_scale = 8.0\nalbedo = [0.9, 0.85, 0.8]\n{medium_extra}\n\
         {lights}\n\
         [integrator]\ntype = \"restir\"\n\
         [render]\npixel_jitter = false\n"
    )
}

const EXPLOSION: &str = "[camera]\nfrom = [0.0, 0.1, 1.9]\nto = [0.0, -0.02, 0.0]\nwidth = 16\nheight = 12\nfov = 40.0\n\
        [[media]]\ndensity = { procedural = \"explosion\", resolution = 32, seed = 3 }\n\
        sigma_t_scale = 10.0\nalbedo = [0.55, 0.55, 0.55]\nphase = { type = \"hg\", g = 0.3 }\n\
        emission = { temperature = { procedural = \"explosion\", quantity = \"temperature\", resolution = 32, seed = 3 }, scale = 40.0 }\n\
        [[lights]]\ntype = \"constant\"\nradiance = [0.02, 0.025, 0.03]\n\
        [integrator]\ntype = \"restir\"\n\
        [render]\npixel_jitter = false\n";

fn scene(text: &str, set: &[String]) -> Scene {
    Scene::build(parse_scene(text, "test", set).unwrap(), Path::new(".")).unwrap()
}

fn opts(spp: u32, seed: u32) -> RenderOptions {
    RenderOptions::new(spp, seed)
}

fn report(what: &str, z: &ZTest, cpu: &Film, gpu: &Film) {
    eprintln!(
        "{what}: pass {} failing {} max|z| {:.2} at {:?} (threshold {:.2}); mean cpu {:.5?} gpu {:.5?}; lookups cpu {} gpu {}",
        z.pass,
        z.failing_pixels,
        z.max_abs_z,
        z.max_abs_z_pixel,
        z.threshold,
        cpu.image_mean(),
        gpu.image_mean(),
        cpu.lookups,
        gpu.lookups
    );
}

/// The CPU without its primary-ray T̃ tables (the same image; the GPU
/// marches every segment, so the two then do the same lookups).
const CPU_MARCHES: &str = "integrator.primary_table=false";

/// CPU `restir` with `cpu_set`, GPU with `gpu_set` (each after `K`).
fn compare_sets(
    gpu: &Gpu,
    text: &str,
    k: u32,
    cpu_set: &[&str],
    gpu_set: &[&str],
    n: u32,
) -> ZTest {
    let with = |extra: &[&str]| {
        let mut v = vec![format!("integrator.max_depth={k}")];
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let mut cpu_with = with(cpu_set);
    cpu_with.push(CPU_MARCHES.to_string());
    let cpu = render(&scene(text, &cpu_with), &opts(n, 1), &Progress::default()).film;
    let g = gpu_render::render(
        gpu,
        &scene(text, &with(gpu_set)),
        &opts(n, 2),
        &Progress::default(),
    )
    .unwrap();
    assert_eq!(g.film.nan_samples, 0, "{gpu_set:?}");
    assert_eq!(g.film.count.iter().min(), Some(&n), "every sequence shaded");
    let z = ztest(&image(&cpu), &image(&g.film)).unwrap();
    report(
        &format!("K={k} cpu {cpu_set:?} gpu {gpu_set:?}"),
        &z,
        &cpu,
        &g.film,
    );
    if cpu_set == gpu_set {
        // The same method does the same work: lookups within 3 %.
        let (lc, lg) = (cpu.lookups as f64, g.film.lookups as f64);
        assert!((lc - lg).abs() <= 0.03 * lc, "lookups cpu {lc} gpu {lg}");
    }
    z
}

fn compare(gpu: &Gpu, text: &str, k: u32, set: &[&str]) -> ZTest {
    compare_sets(gpu, text, k, set, set, SEQUENCES)
}

#[test]
fn restir_gpu_matches_the_cpu_on_lit_clouds() {
    let Some(gpu) = test_gpu() else { return };
    for (lights, extra) in [(ENV, ""), (POINT, "phase = { type = \"hg\", g = 0.7 }")] {
        let text = slab(lights, extra);
        for k in [1, 3] {
            assert!(compare(&gpu, &text, k, &[]).pass, "K = {k}, {lights}");
        }
    }
}

/// Surfaces as path vertices (restir/surface.wgsl): a diffuse
/// card, a rough plastic sheet through the slab, a rough conductor sphere,
/// an emitting rectangle above and an emitting sphere in view — the CPU
/// unbiasedness test's scene (eval/tests/restir_unbiased_test.rs), which
/// also has walks, light sampling and shifted paths cut by shapes. K = 3
/// only (lavapipe's time): it has the directly seen emitters of K = 1.
#[test]
fn restir_gpu_matches_the_cpu_with_reflecting_and_emitting_surfaces() {
    let Some(gpu) = test_gpu() else { return };
    let shapes = include_str!("../../../render/tests/scenes/restir_surfaces.toml");
    let text = slab(shapes, "phase = { type = \"hg\", g = 0.5 }");
    assert!(compare(&gpu, &text, 3, &[]).pass);
}

#[test]
fn restir_gpu_matches_the_cpu_on_the_explosion() {
    let Some(gpu) = test_gpu() else { return };
    // More sequences (the environment's share is a rare, large event under
    // the luminance target; the CPU test against volpath needs 1024).
    for k in [1, 3] {
        assert!(
            compare_sets(&gpu, EXPLOSION, k, &[], &[], 256).pass,
            "K = {k}"
        );
    }
}

#[test]
fn restir_gpu_options_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let text = slab(ENV, "");
    // Each option once, several per image: the reservoir regions of every
    // reuse mode, both shifts, the three unbiased MIS rules (pairwise beyond
    // the paper), exact trilinear free
    // flight for candidates (mip 0), the BC4 mip, and an estimator other
    // than the exact one in final shading.
    for set in [
        &["integrator.reuse=none"][..],
        &[
            "integrator.reuse=spatial",
            "integrator.mis=stochastic",
            "integrator.shift=vertex",
            "integrator.primary_mip=0",
            "integrator.indirect_mip=0",
        ],
        &[
            "integrator.reuse=temporal",
            "integrator.reuse_bc4=true",
            "integrator.estimator=ratio_tracking",
        ],
        &["integrator.mis=pairwise"],
    ] {
        assert!(compare(&gpu, &text, 3, set).pass, "{set:?}");
    }
}

#[test]
fn restir_gpu_with_plain_weights_is_rejected() {
    let Some(gpu) = test_gpu() else { return };
    let text = slab(ENV, "");
    let z = compare_sets(&gpu, &text, 1, &[], &["integrator.mis=uniform"], SEQUENCES);
    assert!(!z.pass, "1/M weights must be told apart from Talbot");
}

/// A point light moving every frame of an 8-frame animation: the GPU's
/// temporal reuse evaluates p̂_prev with the previous frame's light (its
/// bind groups), as the CPU does.
#[test]
fn restir_gpu_matches_the_cpu_with_a_moving_light() {
    let Some(gpu) = test_gpu() else { return };
    let moving = include_str!("../../../render/tests/scenes/restir_moving_light.toml");
    let text = slab(moving, "phase = { type = \"hg\", g = 0.5 }");
    let set = ["integrator.max_depth=3", CPU_MARCHES].map(String::from);
    let desc = parse_scene(&text, "test", &set).unwrap();
    let frames: Vec<Scene> = (0..8)
        .map(|f| Scene::build_frame(desc.clone(), Path::new("."), f).unwrap())
        .collect();
    let (g, times) = last_frames(&gpu, &frames, 2, SEQUENCES).unwrap();
    assert_eq!(times.frames, 8 * SEQUENCES.div_ceil(64));
    let cpu = cpu_last_frames(&frames, 1, SEQUENCES);
    let z = ztest(&image(&cpu), &image(&g)).unwrap();
    report("moving light", &z, &cpu, &g);
    assert!(z.pass);
    // The light did move: the GPU's last frame is not the first frame.
    let first = cpu_last_frames(&frames[..1], 1, SEQUENCES);
    assert!(!ztest(&image(&first), &image(&g)).unwrap().pass);
}

/// The animated plume (8 fps, its density rising and swirling): temporal
/// reuse moves reprojected points back along the plume's velocity, as on
/// the CPU (the velocity only picks which previous reservoir is reused, so
/// this checks the GPU runs it and agrees, not the choice itself: that is
/// `velocity_test` of the GPU crate).
#[test]
fn restir_gpu_matches_the_cpu_on_the_animated_plume() {
    let Some(gpu) = test_gpu() else { return };
    let text = "[camera]\nfrom = [0.0, 0.0, 1.6]\nwidth = 16\nheight = 12\nfov = 40.0\n\
        [[media]]\ndensity = { procedural = \"plume\", resolution = 32, seed = 7 }\n\
        sigma_t_scale = 40.0\nalbedo = [0.9, 0.9, 0.9]\nphase = { type = \"hg\", g = 0.3 }\n\
        [[lights]]\ntype = \"constant\"\nradiance = [0.8, 0.9, 1.0]\n\
        [integrator]\ntype = \"restir\"\nmax_depth = 1\n\
        [render]\npixel_jitter = false\n[animation]\nframes = 4\nfps = 8.0\n";
    let desc = parse_scene(text, "test", &[CPU_MARCHES.to_string()]).unwrap();
    let frames: Vec<Scene> = (0..4)
        .map(|f| Scene::build_frame(desc.clone(), Path::new("."), f).unwrap())
        .collect();
    assert!(frames[3].media[0].velocity.is_some() && frames[3].world.frame_dt > 0.0);
    let (g, _) = last_frames(&gpu, &frames, 2, SEQUENCES).unwrap();
    let cpu = cpu_last_frames(&frames, 1, SEQUENCES);
    let z = ztest(&image(&cpu), &image(&g)).unwrap();
    report("animated plume", &z, &cpu, &g);
    assert!(z.pass);
    let (lc, lg) = (cpu.lookups as f64, g.lookups as f64);
    assert!((lc - lg).abs() <= 0.03 * lc, "lookups cpu {lc} gpu {lg}");
}

/// The CPU's last frames of `n` sequences over `frames`, as a film.
fn cpu_last_frames(frames: &[Scene], seed: u32, n: u32) -> Film {
    use fogbank_render::integrators::restir::frame::Sequence;
    use fogbank_render::integrators::IntegratorKind;
    let restir: Vec<_> = frames
        .iter()
        .map(|s| match &s.integrator {
            IntegratorKind::Restir(r) => r,
            _ => unreachable!(),
        })
        .collect();
    let data: Vec<_> = (0..frames.len())
        .map(|f| restir[f].data(&frames[f].world))
        .collect();
    let cam = &frames[0].camera;
    let mut film = Film::new(cam.width, cam.height);
    for s in 0..n {
        let mut seq = Sequence::new(restir[0], seed, s);
        let mut last = None;
        for f in 0..frames.len() {
            let out = seq.frame(&data[f], &data[f.saturating_sub(1)]);
            film.lookups += out.lookups;
            last = Some(out);
        }
        let out = last.unwrap();
        for (i, l) in out.radiance.iter().enumerate() {
            film.add_sample(i, *l);
        }
    }
    film
}

//! The render loop's scheduling: chunks of samples side
//! by side with submissions in flight give the image of one chunk per
//! dispatch bit for bit, in few submissions.

use crate::integrators::Kernel;
use crate::render::{render_scheduled, Schedule};
use crate::test_gpu;
use fogbank_render::{parse_scene, Progress, RenderOptions, Scene};
use std::path::Path;

fn scene(size: u32, integrator: &str) -> Scene {
    let text = format!(
        "[camera]\nwidth = {size}\nheight = {size}\nfov = 28.0\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = 32, seed = 5 }}\nsigma_t_scale = 12.0\n\
         filter = \"stochastic_trilinear\"\nalbedo = [0.8, 0.8, 0.8]\n\
         [[lights]]\ntype = \"point\"\nposition = [2.0, 2.0, 2.0]\nintensity = [20.0, 20.0, 20.0]\n\
         [integrator]\n{integrator}\n"
    );
    Scene::build(parse_scene(&text, "test", &[]).unwrap(), Path::new(".")).unwrap()
}

fn run(gpu: &crate::Gpu, s: &Scene, spp: u32, schedule: Schedule) -> crate::render::GpuRender {
    let opts = RenderOptions::new(spp, 3);
    let kernel = Kernel::of(s).unwrap();
    render_scheduled(gpu, s, &kernel, &opts, &Progress::default(), None, schedule).unwrap()
}

#[test]
fn filled_schedule_gives_the_sequential_image_bit_for_bit() {
    let Some(gpu) = test_gpu() else { return };
    for integrator in [
        "type = \"transmittance\"\nestimator = \"ratio_tracking\"",
        "type = \"volpath\"\nmax_depth = 3",
    ] {
        let s = scene(20, integrator);
        // 37: the last chunk is partial.
        let a = run(&gpu, &s, 37, Schedule::Sequential);
        let b = run(&gpu, &s, 37, Schedule::Filled);
        assert_eq!(a.film.count, b.film.count, "{integrator}");
        assert!(a.film.count.iter().all(|&c| c == 37));
        assert_eq!(a.film.sums, b.film.sums, "{integrator}");
        assert_eq!(a.film.lookups, b.film.lookups, "{integrator}");
        assert_eq!(a.submits, 10, "{integrator}: one per chunk");
        assert_eq!(b.submits, 1, "{integrator}: 400 pixels × 10 chunks fit one");
    }
}

#[test]
fn small_image_renders_1024_spp_in_at_most_16_submits() {
    let Some(gpu) = test_gpu() else { return };
    let s = scene(
        128,
        "type = \"transmittance\"\nestimator = \"ratio_tracking\"",
    );
    let r = run(&gpu, &s, 1024, Schedule::Filled);
    assert!(r.film.count.iter().all(|&c| c == 1024));
    assert!(r.submits <= 16, "{} submits", r.submits);
}

/// A time budget and a cancellation both stop a long render between
/// submissions with whole chunks accumulated: every pixel has the same
/// count, a multiple of the chunk size, short of the spp asked for.
#[test]
fn time_budget_and_cancel_stop_between_submissions() {
    let Some(gpu) = test_gpu() else { return };
    let s = scene(
        32,
        "type = \"transmittance\"\nestimator = \"ratio_tracking\"",
    );
    let kernel = Kernel::of(&s).unwrap();
    let spp = 1 << 24;
    let budget = RenderOptions {
        spp,
        seed: 1,
        time_budget: Some(std::time::Duration::from_millis(200)),
    };
    let r = render_scheduled(
        &gpu,
        &s,
        &kernel,
        &budget,
        &Progress::default(),
        None,
        Schedule::Filled,
    )
    .unwrap();
    let n = r.film.count[0];
    assert!(n > 0 && n < spp && !r.interrupted, "{n}");
    assert!(r.film.count.iter().all(|&c| c == n));

    let progress = Progress::default();
    let unlimited = RenderOptions {
        time_budget: None,
        ..budget
    };
    let r = std::thread::scope(|t| {
        t.spawn(|| {
            // Cancel once some samples are done (as Ctrl-C would).
            while progress
                .samples_done
                .load(std::sync::atomic::Ordering::Relaxed)
                == 0
            {
                std::thread::yield_now();
            }
            progress
                .cancel
                .store(true, std::sync::atomic::Ordering::Relaxed);
        });
        render_scheduled(
            &gpu,
            &s,
            &kernel,
            &unlimited,
            &progress,
            None,
            Schedule::Filled,
        )
        .unwrap()
    });
    let n = r.film.count[0];
    assert!(r.interrupted && n > 0 && n < spp, "{n}");
    assert!(r.film.count.iter().all(|&c| c == n));
    assert_eq!(n % crate::accumulation::SAMPLES_PER_CHUNK, 0);
}

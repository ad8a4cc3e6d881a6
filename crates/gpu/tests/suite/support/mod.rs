//! Shared by the GPU test binaries.

use fogbank_gpu::{render as gpu_render, Gpu};
use fogbank_image::metrics::ztest;
use fogbank_image::Image;
use fogbank_render::{render, Film, Progress, RenderOptions, Scene};

/// The film as an image for the z-test. The variance gets a floor of
/// (1e-5 · value)²: GPU rays are transformed in f32 (the CPU uses f64), so
/// a grazing ray can meet a near-empty voxel on one side only, and a pixel
/// that is exactly 1 on the CPU may be 0.9999996 on the GPU with no noise
/// on either side.
pub fn image(f: &Film) -> Image {
    let rgb = f.mean();
    let variance = f
        .variance_of_mean()
        .iter()
        .zip(&rgb)
        .map(|(v, m)| [0, 1, 2].map(|c| v[c].max((1e-5 * m[c]).powi(2))))
        .collect();
    Image {
        width: f.width as usize,
        height: f.height as usize,
        rgb,
        variance: Some(variance),
        is_srgb8: false,
    }
}

/// The GPU's render of `s` against the CPU's at `spp` (independent seeds):
/// no non-finite sample, the per-pixel z-test passes, lookups within 3 %,
/// and the scene is lit (image mean above `min_mean`). `what` names the
/// case in messages.
pub fn assert_gpu_matches_cpu(gpu: &Gpu, s: &Scene, spp: u32, min_mean: f64, what: &str) {
    let (lc, lg) = assert_gpu_image_matches_cpu(gpu, s, spp, min_mean, what);
    assert!(
        (lc - lg).abs() <= 0.03 * lc,
        "{what}: lookups cpu {lc} gpu {lg}"
    );
}

/// [`assert_gpu_matches_cpu`] without the lookup count, which it returns
/// (CPU, GPU): for kernels that take other walks to the same expectation.
pub fn assert_gpu_image_matches_cpu(
    gpu: &Gpu,
    s: &Scene,
    spp: u32,
    min_mean: f64,
    what: &str,
) -> (f64, f64) {
    let opts = |seed| RenderOptions::new(spp, seed);
    let cpu = render(s, &opts(1), &Progress::default()).film;
    let g = gpu_render::render(gpu, s, &opts(2), &Progress::default()).unwrap();
    assert_eq!(g.film.nan_samples, 0, "{what}");
    let z = ztest(&image(&cpu), &image(&g.film)).unwrap();
    assert!(
        z.pass,
        "{what}: {} failing pixels, max |z| {:.2} (threshold {:.2}) at {:?}",
        z.failing_pixels, z.max_abs_z, z.threshold, z.max_abs_z_pixel
    );
    let (lc, lg) = (cpu.lookups as f64, g.film.lookups as f64);
    assert!(cpu.image_mean()[0] > min_mean, "the scene must be lit");
    eprintln!(
        "{what}: max |z| {:.2}, failing {}, lookups gpu/cpu {:.3}",
        z.max_abs_z,
        z.failing_pixels,
        lg / lc
    );
    (lc, lg)
}

/// The Mitsuba 3 agreement check shared with `fogbank-render`'s tests.
#[path = "../../../../scene/tests/suite/support/mitsuba_agreement.rs"]
pub mod mitsuba_agreement;

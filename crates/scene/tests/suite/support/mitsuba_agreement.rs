//! The agreement of a render with the Mitsuba 3 `scalar_rgb` reference of
//! a scene of `scenes/mitsuba/` (shared by the CPU's and the GPU's tests),
//! or of a pbrt-v4 scene of `scenes/pbrt/` with its Mitsuba twin's
//! (mirrored) reference: the `_in` forms take the folder holding `refs/`.

use fogbank_image::image_io::{read_image, Image};
use fogbank_image::metrics::ztest::ztest;
use fogbank_render::Film;
use std::path::{Path, PathBuf};

pub fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mitsuba")
}

/// `scenes/pbrt`, whose `refs/` hold its Mitsuba twins' references.
#[allow(dead_code)] // the CPU's suite (pbrt_mitsuba) uses it, the GPU's not
pub fn pbrt_scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/pbrt")
}

/// Relative L1 distance of the 8×8 block means of channel `c`.
fn block_rel_l1(r: &Image, t: &Image, c: usize) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for by in (0..r.height).step_by(8) {
        for bx in (0..r.width).step_by(8) {
            let (mut a, mut b) = (0.0f64, 0.0f64);
            for y in by..(by + 8).min(r.height) {
                for x in bx..(bx + 8).min(r.width) {
                    a += r.rgb[y * r.width + x][c] as f64;
                    b += t.rgb[y * r.width + x][c] as f64;
                }
            }
            num += (a - b).abs();
            den += a.abs();
        }
    }
    num / den.max(1e-12)
}

/// The names of the scenes with a reference in `refs/refs.json` (the GPU's
/// test renders them all; the CPU's has one test per scene).
#[allow(dead_code)] // the GPU's suite uses it, the CPU's not
pub fn reference_scenes() -> Vec<String> {
    let text = std::fs::read_to_string(scenes().join("refs/refs.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut names: Vec<String> = v["scenes"].as_object().unwrap().keys().cloned().collect();
    names.sort();
    names
}

/// A reference's record in `refs/refs.json`: its spp, the noise constant
/// of its 8×8 block relative L1 (≈ k / √samples) and that of its image
/// mean's relative standard error (largest channel).
fn reference_noise(dir: &Path, name: &str) -> (f64, f64, f64) {
    let text = std::fs::read_to_string(dir.join("refs/refs.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let s = &v["scenes"][name];
    let largest = |key: &str| {
        s[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .fold(0.0, f64::max)
    };
    let samples = s["samples"].as_f64().unwrap();
    (
        s["spp"].as_f64().unwrap(),
        largest("block8_rel_l1_x_sqrt_samples_rgb"),
        largest("mean_rel_se_rgb") * samples.sqrt(),
    )
}

/// Samples per pixel of a render of scene `name` that [`assert_agrees`]
/// can judge.
pub fn spp_for(name: &str) -> u32 {
    spp_for_in(&scenes(), name)
}

/// [`spp_for`] of a reference in `dir/refs`.
pub fn spp_for_in(dir: &Path, name: &str) -> u32 {
    let reference = read_image(dir.join(format!("refs/{name}.exr"))).unwrap();
    let pixels = reference.width * reference.height;
    // At least 2·10⁶ samples (Mitsuba's criterion), more where the scene is
    // so noisy that the other two would fail from noise alone: enough for
    // an expected block L1 of 1 % (half the limit) and for the image mean
    // to sit within 1 % at 3σ, allowing fogbank twice Mitsuba's variance
    // (its light selection differs from Mitsuba's uniform one).
    let (ref_spp, k_block, k_mean) = reference_noise(dir, name);
    let ref_samples = ref_spp * pixels as f64;
    let block = 1.0 / ((0.01 / k_block).powi(2) - 1.0 / ref_samples);
    let mean = 2.0 * (3.0 * k_mean / 0.01).powi(2);
    let samples = block.max(mean).clamp(2e6, 2e7);
    (samples / pixels as f64).ceil() as u32
}

/// Scene `name`'s render `film` (at [`spp_for`]'s samples) against its
/// Mitsuba 3 reference: the per-pixel z-test, channel means within 1 %,
/// 8×8 block means within 2 %.
pub fn assert_agrees(name: &str, film: &Film) {
    assert_agrees_in(&scenes(), name, film);
}

/// [`assert_agrees`] with a reference in `dir/refs`.
pub fn assert_agrees_in(dir: &Path, name: &str, film: &Film) {
    let reference = read_image(dir.join(format!("refs/{name}.exr"))).unwrap();
    let (ref_spp, _, _) = reference_noise(dir, name);
    let spp = film.count.iter().copied().min().unwrap_or(0).max(1);
    assert_eq!(film.nan_samples + film.inf_samples, 0, "{name}");
    // The test's variance of the mean is floored by the reference's
    // per-sample variance at the test's spp and by its own mean over the
    // pixel's 3×3 neighbourhood: a pixel whose rare bright samples the test
    // missed would otherwise have both its mean and its variance
    // underestimated and fail although unbiased (Mitsuba's own test judges
    // with the reference's per-sample variance alone; fogbank's samples can
    // be more skewed than Mitsuba's, as where it picks lights by power).
    let floor = ref_spp / spp as f64;
    let reference_var = reference.variance.clone().unwrap();
    let own = film.variance_of_mean();
    let (w, h) = (film.width as usize, film.height as usize);
    let local = |x: usize, y: usize, c: usize| {
        let (mut sum, mut n) = (0.0f64, 0.0f64);
        for yy in y.saturating_sub(1)..(y + 2).min(h) {
            for xx in x.saturating_sub(1)..(x + 2).min(w) {
                sum += own[yy * w + xx][c] as f64;
                n += 1.0;
            }
        }
        (sum / n) as f32
    };
    let variance = (0..w * h)
        .map(|i| {
            [0, 1, 2].map(|c| {
                own[i][c]
                    .max((reference_var[i][c] as f64 * floor) as f32)
                    .max(local(i % w, i / w, c))
            })
        })
        .collect();
    let test = Image {
        width: film.width as usize,
        height: film.height as usize,
        rgb: film.mean(),
        variance: Some(variance),
        is_srgb8: false,
    };
    let z = ztest(&reference, &test).unwrap();
    assert!(
        z.pass,
        "{name}: {} pixels fail the z-test (max |z| {:.2} at {:?}, threshold {:.2}); mean z {:?}",
        z.failing_pixels, z.max_abs_z, z.max_abs_z_pixel, z.threshold, z.mean_z
    );
    for c in 0..3 {
        let mean = |i: &Image| i.rgb.iter().map(|p| p[c] as f64).sum::<f64>() / i.rgb.len() as f64;
        let (r, t) = (mean(&reference), mean(&test));
        assert!(
            (t / r - 1.0).abs() < 0.01,
            "{name}: channel {c} mean {t} vs {r}"
        );
        let l1 = block_rel_l1(&reference, &test, c);
        assert!(
            l1 < 0.02,
            "{name}: channel {c} 8×8 blocks differ by {l1} (relative L1)"
        );
    }
}

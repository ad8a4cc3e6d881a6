//! Environment map light: layout convention, agreement of `sample`, `pdf`
//! and `eval` (chi-square and exact checks), normalisation, degenerate
//! maps, and loading EXR / HDR files (including broken ones).

use fogbank_math::chi2::{adaptive_simpson, sidak, SphereTest, SIGNIFICANCE};
use fogbank_math::Pcg32;
use fogbank_render::lights::envmap::Envmap;
use glam::{DVec3, Mat3, Vec3};
use std::f64::consts::PI;
use std::path::PathBuf;

/// The chi-square tests below share one 1 % false-alarm budget.
const CHI2_TESTS: u32 = 2;

const W: usize = 64;
const H: usize = 32;

/// The documented layout: θ from +y, φ from −z towards +x.
fn layout_direction(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
        (-theta.sin() * phi.cos()) as f32,
    )
}

/// Direction through the centre of pixel (row, col) of a w × h map.
fn pixel_centre(row: usize, col: usize, w: usize, h: usize) -> Vec3 {
    layout_direction(
        PI * (row as f64 + 0.5) / h as f64,
        2.0 * PI * (col as f64 + 0.5) / w as f64,
    )
}

/// A 64 × 32 sky: gradients in both angles, a sun about 200 times brighter
/// than the sky, and a black ground (zero-probability pixels).
fn sky_pixels() -> Vec<[f32; 3]> {
    let mut rgb = Vec::with_capacity(W * H);
    for i in 0..H {
        for j in 0..W {
            let v = (i as f32 + 0.5) / H as f32;
            let u = (j as f32 + 0.5) / W as f32;
            let p = if i >= H - 5 {
                [0.0, 0.0, 0.0]
            } else if (i, j) == (9, 40) {
                [300.0, 280.0, 250.0]
            } else {
                let s = (std::f32::consts::PI * u).sin();
                [0.2 + 0.8 * v, 0.3 + 0.6 * s * s, 1.0 - 0.6 * v]
            };
            rgb.push(p);
        }
    }
    rgb
}

fn rotation() -> Mat3 {
    Mat3::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.9)
}

fn sky(to_world: Mat3) -> Envmap {
    Envmap::from_pixels(W, H, sky_pixels(), 1.5, to_world).unwrap()
}

fn chi2(env: &Envmap) {
    let test = SphereTest::new([32, 64], 1_000_000, 23);
    let r = test.run(
        |rng| Some(env.sample([rng.next_f32(), rng.next_f32()]).0.as_dvec3()),
        |d| env.pdf(d.as_vec3()) as f64,
        0.0,
    );
    r.assert_passes(sidak(SIGNIFICANCE, CHI2_TESTS), 1e-4, "");
}

#[test]
fn chi2_envmap_sun_and_gradient_sky() {
    chi2(&sky(Mat3::IDENTITY));
}

#[test]
fn chi2_envmap_rotated() {
    chi2(&sky(rotation()));
}

/// ∫ f dω by nested adaptive Simpson in (cos θ, φ) about +x, a
/// parameterisation unrelated to the map's pixel grid.
fn sphere_integral(f: impl Fn(Vec3) -> f64) -> f64 {
    let n = 8;
    let mut total = 0.0;
    for a in 0..n {
        let (x0, x1) = (
            -1.0 + 2.0 * a as f64 / n as f64,
            -1.0 + 2.0 * (a + 1) as f64 / n as f64,
        );
        for b in 0..2 * n {
            let (p0, p1) = (PI * b as f64 / n as f64, PI * (b + 1) as f64 / n as f64);
            total += adaptive_simpson(
                &mut |x| {
                    let s = (1.0 - x * x).max(0.0).sqrt();
                    adaptive_simpson(
                        &mut |p| f(DVec3::new(x, s * p.cos(), s * p.sin()).as_vec3()),
                        p0,
                        p1,
                        1e-9,
                    )
                },
                x0,
                x1,
                1e-8,
            );
        }
    }
    total
}

#[test]
fn pdf_integrates_to_one_and_power_is_integral_of_luminance() {
    for env in [sky(Mat3::IDENTITY), sky(rotation())] {
        let integral = sphere_integral(|d| env.pdf(d) as f64);
        assert!((integral - 1.0).abs() < 1e-4, "∫ pdf dω = {integral}");
        let y = |c: Vec3| 0.2126 * c.x as f64 + 0.7152 * c.y as f64 + 0.0722 * c.z as f64;
        let power = sphere_integral(|d| y(env.eval(d)));
        let proxy = env.power_proxy() as f64;
        assert!(
            (power / proxy - 1.0).abs() < 1e-4,
            "∫ Y dω = {power}, proxy {proxy}"
        );
    }
    // A constant environment: 4π Y(L).
    let env = Envmap::from_pixels(8, 4, vec![[1.0, 1.0, 1.0]; 32], 2.0, Mat3::IDENTITY).unwrap();
    assert!((env.power_proxy() as f64 / (8.0 * PI) - 1.0).abs() < 1e-6);
    assert!((env.pdf(Vec3::X) as f64 * 4.0 * PI - 1.0).abs() < 1e-6);
}

#[test]
fn sample_agrees_exactly_with_eval_and_pdf() {
    for to_world in [Mat3::IDENTITY, rotation()] {
        let env = sky(to_world);
        let mut rng = Pcg32::new(9, 10);
        for k in 0..50_000 {
            let mut u = [rng.next_f32(), rng.next_f32()];
            if k == 0 {
                u = [0.0, 0.0];
            } else if k == 1 {
                u = [1.0 - f32::EPSILON / 2.0; 2];
            }
            let (dir, radiance, pdf) = env.sample(u);
            assert!((dir.length() - 1.0).abs() < 1e-5, "u = {u:?}");
            assert!(pdf > 0.0 && pdf.is_finite(), "u = {u:?}");
            assert_eq!(env.eval(dir), radiance, "u = {u:?}");
            assert_eq!(env.pdf(dir), pdf, "u = {u:?}");
            // Never in the black ground.
            assert!(radiance != Vec3::ZERO);
        }
    }
}

#[test]
fn layout_is_mitsuba_lat_long_with_y_up() {
    // Each pixel's red channel is its index.
    let (w, h) = (16, 8);
    let rgb: Vec<[f32; 3]> = (0..w * h).map(|k| [k as f32, 1.0, 1.0]).collect();
    let env = Envmap::from_pixels(w, h, rgb, 1.0, Mat3::IDENTITY).unwrap();
    let index = |d: Vec3| env.eval(d).x as usize;
    assert_eq!(index(Vec3::Y), w / 2, "zenith is the top row");
    assert!(index(-Vec3::Y) >= (h - 1) * w, "nadir is the bottom row");
    // Horizon directions fall in the rows just below and above the middle.
    let horizon = |d: Vec3| index(d.normalize() + Vec3::new(0.0, -1e-3, 0.0)) % w;
    assert_eq!(horizon(Vec3::new(1e-3, 0.0, -1.0)), 0, "φ = 0 is −z");
    assert_eq!(
        horizon(Vec3::new(1.0, 0.0, -1e-3)),
        w / 4 - 1,
        "just before +x"
    );
    assert_eq!(horizon(Vec3::new(1.0, 0.0, 1e-3)), w / 4, "+x is u = 1/4");
    assert_eq!(horizon(Vec3::new(-1e-3, 0.0, 1.0)), w / 2, "+z is u = 1/2");
    assert_eq!(
        horizon(Vec3::new(-1.0, 0.0, 1e-3)),
        3 * w / 4 - 1,
        "−x is u = 3/4"
    );
    for row in 0..h {
        for col in 0..w {
            assert_eq!(index(pixel_centre(row, col, w, h)), row * w + col);
        }
    }
    // to_world rotates the map: a lookup in world space equals the local
    // lookup of the rotated-back direction.
    let r = rotation();
    let rotated = Envmap::from_pixels(
        w,
        h,
        (0..w * h).map(|k| [k as f32, 1.0, 1.0]).collect(),
        1.0,
        r,
    )
    .unwrap();
    for row in 0..h {
        for col in 0..w {
            let d = pixel_centre(row, col, w, h);
            assert_eq!(rotated.eval(r * d).x as usize, row * w + col);
        }
    }
}

#[test]
fn black_map_has_zero_pdf_and_no_nan() {
    let env = Envmap::from_pixels(W, H, vec![[0.0; 3]; W * H], 1.0, rotation()).unwrap();
    assert_eq!(env.power_proxy(), 0.0);
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..1000 {
        let (dir, radiance, pdf) = env.sample([rng.next_f32(), rng.next_f32()]);
        assert!(dir.is_finite() && (dir.length() - 1.0).abs() < 1e-5);
        assert_eq!((radiance, pdf), (Vec3::ZERO, 0.0));
        assert_eq!(env.pdf(dir), 0.0);
        assert_eq!(env.eval(dir), Vec3::ZERO);
    }
    // Scale 0 makes any map black.
    let env = Envmap::from_pixels(W, H, sky_pixels(), 0.0, Mat3::IDENTITY).unwrap();
    assert_eq!(env.sample([0.3, 0.7]).2, 0.0);
}

#[test]
fn non_finite_and_negative_pixels_are_zero_and_counted() {
    let (w, h) = (8, 4);
    let mut rgb = vec![[1.0f32, 1.0, 1.0]; w * h];
    rgb[3] = [f32::NAN, 1.0, 1.0];
    rgb[10] = [f32::INFINITY, 0.0, 0.0];
    rgb[17] = [0.0, f32::NEG_INFINITY, 0.0];
    rgb[20] = [-1.0, 2.0, 2.0];
    let env = Envmap::from_pixels(w, h, rgb, 1.0, Mat3::IDENTITY).unwrap();
    assert_eq!(env.non_finite_pixels(), 3);
    assert_eq!(env.negative_pixels(), 1);
    assert_eq!(env.eval(pixel_centre(0, 3, w, h)), Vec3::ZERO);
    assert_eq!(env.eval(pixel_centre(1, 2, w, h)), Vec3::ZERO);
    assert_eq!(env.eval(pixel_centre(2, 1, w, h)), Vec3::ZERO);
    assert_eq!(env.pdf(pixel_centre(2, 1, w, h)), 0.0);
    assert_eq!(env.eval(pixel_centre(2, 4, w, h)), Vec3::new(0.0, 2.0, 2.0));
    let mut rng = Pcg32::new(2, 2);
    for _ in 0..10_000 {
        let (_, radiance, pdf) = env.sample([rng.next_f32(), rng.next_f32()]);
        assert!(radiance.is_finite() && pdf.is_finite() && pdf > 0.0);
        assert!(radiance != Vec3::ZERO);
    }
}

#[test]
fn invalid_arguments_are_errors() {
    assert!(Envmap::from_pixels(0, 4, vec![], 1.0, Mat3::IDENTITY).is_err());
    assert!(Envmap::from_pixels(4, 4, vec![[1.0; 3]; 15], 1.0, Mat3::IDENTITY).is_err());
    assert!(Envmap::from_pixels(4, 4, vec![[1.0; 3]; 16], -1.0, Mat3::IDENTITY).is_err());
    assert!(Envmap::from_pixels(4, 4, vec![[1.0; 3]; 16], f32::NAN, Mat3::IDENTITY).is_err());
    let err = Envmap::from_pixels(
        4,
        4,
        vec![[1.0; 3]; 16],
        1.0,
        Mat3::from_diagonal(Vec3::splat(2.0)),
    )
    .unwrap_err();
    assert!(err.contains("rotation"), "{err}");
}

fn temp_path(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("envmap_test");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn exr_round_trip_rgb_float_and_rgba_half() {
    let (w, h) = (24, 12);
    let value = |x: usize, y: usize| {
        [
            0.25 + x as f32 * 0.5,
            1.0 + y as f32 * 0.125,
            if (x, y) == (5, 3) { 1000.0 } else { 0.5 },
        ]
    };
    let rgb_path = temp_path("rgb_float.exr");
    exr::prelude::write_rgb_file(&rgb_path, w, h, |x, y| {
        let v = value(x, y);
        (v[0], v[1], v[2])
    })
    .unwrap();
    let rgba_path = temp_path("rgba_half.exr");
    exr::prelude::write_rgba_file(&rgba_path, w, h, |x, y| {
        let v = value(x, y).map(half::f16::from_f32);
        (v[0], v[1], v[2], half::f16::ONE)
    })
    .unwrap();
    for path in [&rgb_path, &rgba_path] {
        let env = Envmap::load(path, 2.0, Mat3::IDENTITY).unwrap();
        assert_eq!((env.width(), env.height()), (w, h));
        for y in 0..h {
            for x in 0..w {
                // All test values are exact in f16.
                let expected = Vec3::from(value(x, y)) * 2.0;
                assert_eq!(
                    env.eval(pixel_centre(y, x, w, h)),
                    expected,
                    "{path:?} ({x}, {y})"
                );
            }
        }
    }
}

#[test]
fn hdr_round_trip() {
    let (w, h) = (16, 8);
    let value = |x: usize, y: usize| [0.5 + x as f32, 0.25 * (1 + y) as f32, 2.0];
    let pixels: Vec<image::Rgb<f32>> = (0..w * h)
        .map(|k| image::Rgb(value(k % w, k / w)))
        .collect();
    let path = temp_path("sky.hdr");
    let file = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&pixels, w, h)
        .unwrap();
    let env = Envmap::load(&path, 1.0, Mat3::IDENTITY).unwrap();
    assert_eq!((env.width(), env.height()), (w, h));
    for y in 0..h {
        for x in 0..w {
            let got = env.eval(pixel_centre(y, x, w, h));
            let expected = Vec3::from(value(x, y));
            // RGBE keeps 8 bits of mantissa per channel, relative to the
            // largest channel.
            assert!(
                (got - expected).abs().max_element() < 0.01 * expected.max_element(),
                "({x}, {y}): {got} vs {expected}"
            );
        }
    }
}

#[test]
fn broken_files_are_errors_naming_the_file() {
    // A valid EXR cut in half.
    let good = temp_path("good.exr");
    exr::prelude::write_rgb_file(&good, 32, 16, |x, y| (x as f32, y as f32, 1.0f32)).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let truncated = temp_path("truncated.exr");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    // Header only.
    let header_only = temp_path("header_only.exr");
    std::fs::write(&header_only, &bytes[..40]).unwrap();
    // A Radiance header with no pixels.
    let hdr = temp_path("truncated.hdr");
    std::fs::write(
        &hdr,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n\x02\x02",
    )
    .unwrap();
    // Neither format.
    let garbage = temp_path("garbage.exr");
    std::fs::write(&garbage, b"this is not an image").unwrap();
    let missing = temp_path("does_not_exist.exr");
    for path in [&truncated, &header_only, &hdr, &garbage, &missing] {
        let err = Envmap::load(path, 1.0, Mat3::IDENTITY).unwrap_err();
        assert!(err.contains(&path.display().to_string()), "{err}");
        println!("{err}");
    }
}

/// Mitsuba 3's bilinear reading (`filter = "bilinear"`): texel (row i,
/// column j) sits at θ = π i/(H − 1), φ = 2π (j + ½)/W; between texels the
/// radiance is interpolated, columns wrap around; samples carry that
/// radiance with the piecewise-constant pdf.
#[test]
fn bilinear_lookup_is_mitsubas() {
    let (w, h) = (4usize, 3usize);
    let rgb: Vec<[f32; 3]> = (0..w * h).map(|k| [k as f32, 0.0, 1.0]).collect();
    let env = Envmap::from_pixels(w, h, rgb, 1.0, Mat3::IDENTITY)
        .unwrap()
        .bilinear();
    let at = |theta: f64, phi: f64| env.eval(layout_direction(theta, phi));
    // Row 1 (the horizon), column 2's centre: texel value 6.
    assert!((at(PI / 2.0, 2.0 * PI * 2.5 / 4.0).x - 6.0).abs() < 1e-4);
    // Halfway between columns 3 and 0 (wrapping) on row 1: (7 + 4) / 2.
    assert!((at(PI / 2.0, 0.0).x - 5.5).abs() < 1e-4);
    // A quarter of the way from row 1 to row 2, column 1: 5 + 0.25·4.
    let x = at(PI * 1.25 / 2.0, 2.0 * PI * 1.5 / 4.0).x;
    assert!((x - 6.0).abs() < 1e-4, "{x}");
    let mut rng = Pcg32::new(1, 1);
    for _ in 0..100 {
        let (d, l, _) = env.sample([rng.next_f32(), rng.next_f32()]);
        assert_eq!(l, env.eval(d));
    }
}

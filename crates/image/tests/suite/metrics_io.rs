//! Reading images for comparison: fogbank's EXR layout, other tools' RGBA
//! EXR, sRGB PNG, and every kind of bad input as an error naming the file.

use exr::prelude::{
    f16, AnyChannel, AnyChannels, Encoding, FlatSamples, LayerAttributes, WritableImage,
};
use fogbank_image::image_io::srgb_to_linear;
use fogbank_image::metrics::{read_image, read_pair, rmse};
use std::path::{Path, PathBuf};

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("metrics_io")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes channels of one part the way fogbank's `output::write_exr` does.
fn write_channels(path: &Path, w: usize, h: usize, channels: &[(&str, Vec<f32>)]) {
    let list: Vec<AnyChannel<FlatSamples>> = channels
        .iter()
        .map(|(n, v)| AnyChannel::new(*n, FlatSamples::F32(v.clone())))
        .collect();
    let layer = exr::prelude::Layer::new(
        (w, h),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(list.into()),
    );
    exr::prelude::Image::from_layer(layer)
        .write()
        .to_file(path)
        .unwrap();
}

fn fogbank_exr(path: &Path, w: usize, h: usize, with_variance: bool) {
    let ramp = |k: f32| (0..w * h).map(|i| i as f32 * k).collect::<Vec<f32>>();
    let mut ch = vec![("R", ramp(0.1)), ("G", ramp(0.2)), ("B", ramp(0.3))];
    if with_variance {
        ch.push(("variance.R", ramp(0.01)));
        ch.push(("variance.G", ramp(0.02)));
        ch.push(("variance.B", ramp(0.03)));
    }
    write_channels(path, w, h, &ch);
}

#[test]
fn reads_fogbank_exr_with_variance() {
    let p = dir("fogbank").join("render.exr");
    fogbank_exr(&p, 5, 3, true);
    let img = read_image(&p).unwrap();
    assert_eq!((img.width, img.height), (5, 3));
    assert!(!img.is_srgb8);
    // Row-major, top row first: pixel (x, y) = y·5 + x.
    assert_eq!(img.rgb[7], [0.7, 1.4, 7.0 * 0.3]);
    let v = img.variance.unwrap();
    assert_eq!(v[7], [0.07, 0.14, 7.0 * 0.03]);

    let q = dir("fogbank").join("novar.exr");
    fogbank_exr(&q, 5, 3, false);
    assert!(read_image(&q).unwrap().variance.is_none());
}

#[test]
fn reads_rgba_half_exr_from_other_tools() {
    let p = dir("rgba").join("half.exr");
    exr::prelude::write_rgba_file(&p, 4, 2, |x, y| {
        let v = f16::from_f32(0.25 * x as f32 + y as f32);
        (
            v,
            f16::from_f32(2.0),
            f16::from_f32(0.5),
            f16::from_f32(1.0),
        )
    })
    .unwrap();
    let img = read_image(&p).unwrap();
    assert_eq!((img.width, img.height), (4, 2));
    assert_eq!(img.rgb[5], [1.25, 2.0, 0.5]);
    assert!(img.variance.is_none());
}

#[test]
fn reads_png_as_linear_and_marks_it_srgb() {
    let p = dir("png").join("img.png");
    let bytes: Vec<u8> = vec![0, 128, 255, 10, 20, 30];
    image::save_buffer(&p, &bytes, 2, 1, image::ColorType::Rgb8).unwrap();
    let img = read_image(&p).unwrap();
    assert!(img.is_srgb8);
    assert_eq!(img.rgb[0][0], 0.0);
    assert_eq!(img.rgb[0][2], 1.0);
    assert!(
        (img.rgb[0][1] - 0.2158605).abs() < 1e-6,
        "{}",
        img.rgb[0][1]
    );
    assert_eq!(img.rgb[1][1], srgb_to_linear(20.0 / 255.0));
    // Grey-with-alpha PNGs expand to RGB.
    let q = dir("png").join("la.png");
    image::save_buffer(&q, &[200, 255], 1, 1, image::ColorType::La8).unwrap();
    let img = read_image(&q).unwrap();
    assert_eq!(img.rgb[0], [srgb_to_linear(200.0 / 255.0); 3]);
}

#[test]
fn nonexistent_file_is_an_error_naming_it() {
    let p = dir("bad").join("does_not_exist.exr");
    let e = read_image(&p).unwrap_err();
    assert!(e.contains("does_not_exist.exr"), "{e}");
}

#[test]
fn truncated_and_garbage_files_are_errors() {
    let d = dir("bad");
    let good = d.join("good.exr");
    fogbank_exr(&good, 64, 48, true);
    let bytes = std::fs::read(&good).unwrap();
    for cut in [3, 8, 40, bytes.len() / 2, bytes.len() - 5] {
        let p = d.join(format!("truncated_{cut}.exr"));
        std::fs::write(&p, &bytes[..cut]).unwrap();
        let e = read_image(&p).unwrap_err();
        assert!(e.contains(&format!("truncated_{cut}.exr")), "{e}");
    }
    // Corrupt bytes after a valid header.
    let mut corrupt = bytes.clone();
    let n = corrupt.len();
    for b in &mut corrupt[n / 3..] {
        *b = b.wrapping_mul(31).wrapping_add(7);
    }
    let p = d.join("corrupt.exr");
    std::fs::write(&p, &corrupt).unwrap();
    assert!(read_image(&p).unwrap_err().contains("corrupt.exr"));

    let png = d.join("good.png");
    image::save_buffer(&png, &[7u8; 3 * 16 * 16], 16, 16, image::ColorType::Rgb8).unwrap();
    let bytes = std::fs::read(&png).unwrap();
    let p = d.join("truncated.png");
    std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
    assert!(read_image(&p).unwrap_err().contains("truncated.png"));

    let p = d.join("text.exr");
    std::fs::write(&p, "not an image").unwrap();
    let e = read_image(&p).unwrap_err();
    assert!(
        e.contains("text.exr") && e.contains("not an EXR or PNG"),
        "{e}"
    );
    let p = d.join("empty.png");
    std::fs::write(&p, "").unwrap();
    assert!(read_image(&p).unwrap_err().contains("empty.png"));
}

#[test]
fn missing_channels_are_errors() {
    let d = dir("channels");
    let p = d.join("depth_only.exr");
    write_channels(&p, 2, 2, &[("Z", vec![1.0; 4])]);
    let e = read_image(&p).unwrap_err();
    assert!(e.contains("depth_only.exr") && e.contains("Z"), "{e}");

    let p = d.join("half_variance.exr");
    write_channels(
        &p,
        2,
        2,
        &[
            ("R", vec![1.0; 4]),
            ("G", vec![1.0; 4]),
            ("B", vec![1.0; 4]),
            ("variance.R", vec![1.0; 4]),
        ],
    );
    let e = read_image(&p).unwrap_err();
    assert!(
        e.contains("half_variance.exr") && e.contains("variance.G"),
        "{e}"
    );
}

#[test]
fn size_mismatch_names_both_files() {
    let d = dir("pair");
    let (a, b) = (d.join("big.exr"), d.join("small.exr"));
    fogbank_exr(&a, 8, 6, false);
    fogbank_exr(&b, 6, 8, false);
    let e = read_pair(&a, &b).unwrap_err();
    assert!(e.contains("big.exr") && e.contains("small.exr"), "{e}");
    assert!(e.contains("8×6") && e.contains("6×8"), "{e}");
    // A PNG and an EXR of the same size compare (on linear values).
    let png = d.join("black.png");
    image::save_buffer(&png, &[0u8; 3 * 48], 8, 6, image::ColorType::Rgb8).unwrap();
    let (r, t) = read_pair(&png, &a).unwrap();
    assert!(rmse(&r, &t).unwrap() > 0.0);
}

#[test]
fn written_exr_and_png_read_back() {
    use fogbank_image::image_io::{write_exr, write_png};
    let d = dir("roundtrip");
    let rgb: Vec<[f32; 3]> = (0..6).map(|i| [i as f32 * 0.1, 0.5, 2.0]).collect();
    let var: Vec<[f32; 3]> = (0..6).map(|i| [i as f32 * 0.01, 0.02, 0.03]).collect();
    write_exr(&d.join("a.exr"), 3, 2, &rgb, Some(&var)).unwrap();
    let img = read_image(d.join("a.exr")).unwrap();
    assert_eq!((img.width, img.height), (3, 2));
    assert!(!img.is_srgb8);
    assert_eq!(img.rgb, rgb);
    assert_eq!(img.variance.as_deref(), Some(&var[..]));
    write_exr(&d.join("b.exr"), 3, 2, &rgb, None).unwrap();
    assert!(read_image(d.join("b.exr")).unwrap().variance.is_none());

    // 8-bit sRGB, clamped to [0, 1]: back within a quantisation step.
    write_png(&d.join("a.png"), 3, 2, &rgb, &Default::default()).unwrap();
    let png = read_image(d.join("a.png")).unwrap();
    assert!(png.is_srgb8);
    for (p, q) in png.rgb.iter().zip(&rgb) {
        for c in 0..3 {
            assert!((p[c] - q[c].min(1.0)).abs() < 0.005, "{p:?} vs {q:?}");
        }
    }
}

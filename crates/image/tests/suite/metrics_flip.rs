//! FLIP against NVIDIA's reference implementation (`flip-evaluator` on
//! PyPI): the fixture pairs and reference means come from
//! `tools/check_flip.py --generate`.

use fogbank_image::metrics::{flip, flip_with, read_pair, FlipMode, FlipOptions, Image};
use std::path::{Path, PathBuf};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/metrics")
}

#[test]
fn flip_matches_reference_implementation() {
    let doc: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(fixtures().join("flip_reference.json")).unwrap(),
    )
    .unwrap();
    let pairs = doc["pairs"].as_array().unwrap();
    assert!(pairs.len() >= 3);
    let mut worst = 0f64;
    for p in pairs {
        let name = p["name"].as_str().unwrap();
        let (r, t) = read_pair(
            fixtures().join(p["reference"].as_str().unwrap()),
            fixtures().join(p["test"].as_str().unwrap()),
        )
        .unwrap();
        let ours = flip(&r, &t).unwrap();
        let want = p["mean"].as_f64().unwrap();
        let hdr = p["mode"] == "HDR";
        assert_eq!(ours.hdr, hdr, "{name}: LDR/HDR chosen from the file types");
        let diff = (ours.mean - want).abs();
        println!(
            "{name:<15} reference {want:.6} ours {:.6} |diff| {diff:.2e}",
            ours.mean
        );
        assert!(
            diff <= 1e-3,
            "{name}: ours {} vs reference {want}",
            ours.mean
        );
        worst = worst.max(diff);
        if hdr {
            let e = ours.exposures.unwrap();
            assert!((e.start as f64 - p["start_exposure"].as_f64().unwrap()).abs() < 1e-4);
            assert!((e.stop as f64 - p["stop_exposure"].as_f64().unwrap()).abs() < 1e-4);
            assert_eq!(e.count as u64, p["num_exposures"].as_u64().unwrap());
        }
        assert!((ours.ppd as f64 - p["ppd"].as_f64().unwrap()).abs() < 1e-4);
        assert_eq!(ours.map.len(), r.width * r.height);
        assert!(ours.map.iter().all(|&e| (0.0..=1.0).contains(&e)));
    }
    println!("largest |ours − reference| = {worst:.2e}");
}

#[test]
fn identical_images_have_zero_error() {
    let (r, _) = read_pair(
        fixtures().join("hdr_noise_ref.exr"),
        fixtures().join("hdr_noise_test.exr"),
    )
    .unwrap();
    let f = flip(&r, &r).unwrap();
    assert_eq!(f.mean, 0.0);
    let ldr = flip_with(
        &r,
        &r,
        &FlipOptions {
            mode: FlipMode::Ldr,
            ..FlipOptions::default()
        },
    )
    .unwrap();
    assert_eq!(ldr.mean, 0.0);
    assert!(!ldr.hdr);
}

#[test]
fn error_grows_with_the_difference() {
    // A flat grey against brighter copies: FLIP increases monotonically and
    // stays in [0, 1]; black against white is close to the maximum.
    let r = Image::filled(32, 32, [0.2; 3]);
    let mut last = 0.0;
    for k in [1.05f32, 1.2, 1.6, 3.0] {
        let t = Image::filled(32, 32, [0.2 * k; 3]);
        let m = flip(&r, &t).unwrap().mean;
        assert!(m > last && m <= 1.0, "{k}: {m} after {last}");
        last = m;
    }
    let black = Image::filled(16, 16, [0.0; 3]);
    let white = Image::filled(16, 16, [1.0; 3]);
    let opts = FlipOptions {
        mode: FlipMode::Ldr,
        ..FlipOptions::default()
    };
    let m = flip_with(&black, &white, &opts).unwrap().mean;
    assert!(m > 0.9, "black vs white: {m}");
}

#[test]
fn black_reference_does_not_break_hdr_exposures() {
    // The reference's exposure range would be infinite; ours stays finite.
    let r = Image::filled(8, 8, [0.0; 3]);
    let mut t = r.clone();
    t.rgb[10] = [5.0, 5.0, 5.0];
    let f = flip(&r, &t).unwrap();
    assert!(f.mean.is_finite() && f.mean > 0.0);
    let mut half_black = Image::filled(8, 8, [0.0; 3]);
    for p in &mut half_black.rgb[40..] {
        *p = [2.0; 3];
    }
    let f = flip(&half_black, &t).unwrap();
    assert!(f.mean.is_finite());
}

//! rmse, relmse, smape and the normal quantile on hand-computed cases.

use fogbank_image::metrics::normal::{erfc, normal_quantile};
use fogbank_image::metrics::{relmse, rmse, smape, Image, Metric};

fn img(px: &[[f32; 3]]) -> Image {
    Image::new(px.len(), 1, px.to_vec())
}

fn close(got: f64, want: f64, tol: f64) {
    assert!((got - want).abs() <= tol, "got {got}, want {want}");
}

#[test]
fn rmse_hand_computed() {
    let r = img(&[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
    let t = img(&[[0.1, 0.2, 0.3], [1.0, 1.0, 1.0]]);
    // (0.01 + 0.04 + 0.09) / 6 = 0.14 / 6
    close(rmse(&r, &t).unwrap(), (0.14f64 / 6.0).sqrt(), 1e-7);
    close(rmse(&r, &r).unwrap(), 0.0, 0.0);
    // Symmetric.
    close(rmse(&t, &r).unwrap(), rmse(&r, &t).unwrap(), 0.0);
}

#[test]
fn relmse_hand_computed() {
    let r = img(&[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
    let t = img(&[[0.1, 0.2, 0.3], [1.0, 1.0, 1.0]]);
    // (0.01 + 0.04 + 0.09) / 0.01 / 6 = 14 / 6
    close(relmse(&r, &t).unwrap(), 14.0 / 6.0, 1e-5);
    // ε = 0.01 is added to ref²: (2 − 1)² / (1 + 0.01).
    let r = img(&[[1.0, 1.0, 1.0]]);
    let t = img(&[[2.0, 2.0, 2.0]]);
    close(relmse(&r, &t).unwrap(), 1.0 / 1.01, 1e-9);
}

#[test]
fn smape_hand_computed() {
    let r = img(&[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
    let t = img(&[[0.1, 0.2, 0.3], [1.0, 1.0, 1.0]]);
    // Pixel 0: mean |d| = 0.2, denominator (0.2 + 0)/2 + 0.01 = 0.11.
    close(smape(&r, &t).unwrap(), (0.2 / 0.11) / 2.0, 1e-6);
    // Colour errors do not cancel: red vs green has equal RGB means.
    let r = img(&[[1.0, 0.0, 0.0]]);
    let t = img(&[[0.0, 1.0, 0.0]]);
    close(
        smape(&r, &t).unwrap(),
        (2.0 / 3.0) / (1.0 / 3.0 + 0.01),
        1e-9,
    );
    // Grey values: |t − r| / ((t + r)/2 + ε).
    let r = img(&[[0.5; 3]]);
    let t = img(&[[0.7; 3]]);
    close(smape(&r, &t).unwrap(), 0.2 / (0.6 + 0.01), 1e-6);
    // Symmetric, and bounded by 2.
    close(smape(&t, &r).unwrap(), smape(&r, &t).unwrap(), 1e-12);
    let big = smape(&img(&[[0.0; 3]]), &img(&[[1e6; 3]])).unwrap();
    assert!(big < 2.0 && big > 1.99);
}

#[test]
fn size_mismatch_is_an_error() {
    let a = Image::filled(4, 3, [0.5; 3]);
    let b = Image::filled(3, 4, [0.5; 3]);
    for e in [
        rmse(&a, &b).unwrap_err(),
        relmse(&a, &b).unwrap_err(),
        smape(&a, &b).unwrap_err(),
        fogbank_image::metrics::flip(&a, &b).unwrap_err(),
    ] {
        assert!(e.contains("4×3") && e.contains("3×4"), "{e}");
    }
    // An Image whose pixel array disagrees with its size does not panic.
    let mut bad = Image::filled(2, 2, [0.0; 3]);
    bad.rgb.pop();
    assert!(rmse(&bad, &bad).is_err());
}

#[test]
fn metric_names_parse() {
    assert_eq!(Metric::parse("all").unwrap(), Metric::ALL.to_vec());
    assert_eq!(Metric::parse("FLIP").unwrap(), vec![Metric::Flip]);
    assert!(Metric::parse("psnr").unwrap_err().contains("psnr"));
}

#[test]
fn erfc_matches_reference_values() {
    // Values from CPython's math.erfc.
    for (x, want) in [
        (0.1, 0.8875370839817152),
        (0.5, 0.4795001221869535),
        (1.0, 0.15729920705028513),
        (2.0, 0.004677734981047265),
        (2.5, 0.0004069520174449589),
        (3.0, 2.2090496998585438e-05),
        (4.0, 1.541725790028002e-08),
        (6.0, 2.1519736712498916e-17),
        (10.0, 2.088487583762545e-45),
    ] {
        let got = erfc(x);
        assert!(
            (got / want - 1.0).abs() < 1e-12,
            "erfc({x}) = {got}, want {want}"
        );
        assert!((erfc(-x) - (2.0 - want)).abs() < 1e-15);
    }
}

#[test]
fn normal_quantile_matches_reference_values() {
    // Values from CPython's statistics.NormalDist().inv_cdf.
    for (p, want) in [
        (1e-300, -37.0470962993612),
        (1e-20, -9.262340089798405),
        (1e-10, -6.361340902404056),
        (1e-9, -5.9978070150076865),
        (1e-5, -4.2648907939228256),
        (0.001, -3.090232306167813),
        (0.02425, -1.9729610513118845),
        (0.025, -1.9599639845400538),
        (0.3, -0.5244005127080407),
        (0.5, 0.0),
        (0.975, 1.9599639845400536),
        (0.995, 2.5758293035489),
    ] {
        let got = normal_quantile(p);
        assert!(
            (got - want).abs() <= 1e-12 * want.abs().max(1.0),
            "quantile({p}) = {got}, want {want}"
        );
    }
    assert_eq!(normal_quantile(0.0), f64::NEG_INFINITY);
    assert_eq!(normal_quantile(1.0), f64::INFINITY);
    assert!(normal_quantile(1.5).is_nan());
}

//! `volpath` against analytic answers.

use fogbank_render::{parse_scene, render, Progress, RenderOptions, Scene};
use std::path::Path;

fn scene(extra: &[String]) -> Scene {
    let text = "[camera]\nwidth = 12\nheight = 10\nfov = 50.0\n\
                [[media]]\ndensity = { procedural = \"cloud\", resolution = 24, seed = 2 }\nsigma_t_scale = 12.0\n\
                albedo = [1.0, 1.0, 1.0]\nphase = { type = \"hg\", g = 0.6 }\n\
                [[lights]]\ntype = \"constant\"\nradiance = [1.0, 1.0, 1.0]\n\
                [integrator]\ntype = \"volpath\"\nmax_depth = 10000\n";
    Scene::build(parse_scene(text, "test", extra).unwrap(), Path::new(".")).unwrap()
}

/// White furnace: albedo 1 under a uniform unit environment, every pixel
/// sees radiance 1 whatever the density, for every unbiased configuration.
#[test]
fn white_furnace_for_every_unbiased_configuration() {
    for sampler in [
        "delta_tracking",
        "decomposition_tracking",
        "regular_tracking",
    ] {
        for nee in [
            "ratio_tracking",
            "track_length",
            "residual_ratio_tracking",
            "unbiased_ray_marching",
        ] {
            let s = scene(&[
                format!("integrator.distance_sampler={sampler}"),
                format!("integrator.estimator={nee}"),
                "media.0.filter=nearest".into(),
            ]);
            let r = render(&s, &RenderOptions::new(64, 1), &Progress::default());
            let f = &r.film;
            let n = f.total_samples() as f64;
            // Pool all samples of the image: mean and its standard error.
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for i in 0..f.sums.len() {
                sum += f.sum(i)[0];
                sum2 += f.sum_sq(i)[0];
            }
            let mean = sum / n;
            let se = ((sum2 / n - mean * mean) / n).sqrt();
            assert!(
                (mean - 1.0).abs() < 4.0 * se + 1e-4,
                "{sampler} + {nee}: furnace mean {mean} (se {se})"
            );
            assert_eq!(f.nan_samples + f.inf_samples, 0);
        }
    }
}

/// An absorbing-only medium (albedo 0) under a unit environment: each pixel
/// sees exactly the transmittance of its primary ray, which
/// `analytic_trilinear` gives in closed form.
#[test]
fn absorbing_medium_matches_analytic_trilinear_transmittance() {
    let overrides = |extra: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = vec![
            "media.0.albedo=[0.0, 0.0, 0.0]".into(),
            "render.pixel_jitter=false".into(),
        ];
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    for sampler in ["delta_tracking", "decomposition_tracking"] {
        let s = scene(&overrides(&[&format!(
            "integrator.distance_sampler={sampler}"
        )]));
        let r = render(&s, &RenderOptions::new(256, 2), &Progress::default());
        let mut exact_scene = scene(&overrides(&[
            "integrator.type=\"transmittance\"",
            "integrator.estimator=analytic_trilinear",
        ]));
        exact_scene.world.pixel_jitter = false;
        let exact = render(
            &exact_scene,
            &RenderOptions::new(1, 0),
            &Progress::default(),
        )
        .film
        .mean();
        let f = &r.film;
        let mean = f.mean();
        let var = f.variance_of_mean();
        // Pooled over pixels: Σ(mean − exact) against its standard error.
        let diff: f64 = mean
            .iter()
            .zip(&exact)
            .map(|(m, e)| (m[0] - e[0]) as f64)
            .sum();
        let se: f64 = var.iter().map(|v| v[0] as f64).sum::<f64>().sqrt();
        assert!(
            diff.abs() < 4.0 * se + 1e-6,
            "{sampler}: Σ(volpath − exact) = {diff} (se {se})"
        );
        assert!(se > 0.0);
    }
}

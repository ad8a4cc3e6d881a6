//! Peters 2025's findings on bias and noise of the transmittance estimators
//! (Figs. 8–10), measured against `analytic_trilinear` over 16384 independent
//! frames on two procedural clouds and the Houdini dragon.

use fogbank_estimators::estimator::AnalyticTrilinear;
use fogbank_estimators::{Estimator, Options};
use fogbank_eval::{transmittance_stats, Summary};
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

/// The per-pixel bias of the jackknife (≈ 1e-4) sits below the noise of a
/// 4096-frame mean (std/64 ≈ 3e-4); 16384 frames halve that floor so mean
/// |bias| measures bias, not noise.
const RUNS: u32 = 16384;

fn scene(text: &str) -> Scene {
    Scene::build(parse_scene(text, "test", &[]).unwrap(), Path::new(".")).unwrap()
}

/// Rescales every medium so the largest exact optical depth over the
/// pixel-centre rays is `tau_max`.
fn normalise(mut s: Scene, tau_max: f64) -> Scene {
    let exact = transmittance_stats(
        &s,
        Estimator::AnalyticTrilinear(AnalyticTrilinear),
        None,
        1,
        0,
    );
    let deepest = exact.mean.iter().map(|t| -t[0].ln()).fold(0.0, f64::max);
    for m in &mut s.media {
        let k = (tau_max / deepest) as f32;
        let mut medium = m.medium.clone();
        medium.sigma_t_scale *= k;
        medium.supervoxels = medium.supervoxels.scaled(k);
        m.medium = medium;
    }
    s
}

fn cloud(res: u32, seed: u64) -> Scene {
    let text = format!(
        "[camera]\nfrom = [0.0, 0.1, 1.6]\nto = [0.0, 0.0, 0.0]\nfov = 45.0\nwidth = 24\nheight = 24\n\
         [[media]]\ndensity = {{ procedural = \"cloud\", resolution = {res}, seed = {seed} }}\nsigma_t_scale = 1.0\n"
    );
    normalise(scene(&text), 5.0)
}

fn dragon() -> Scene {
    let p = fogbank_math::sample_data::committed("dragon.vdb");
    let text = format!(
        "[camera]\nfrom = [5.0, 3.0, 14.0]\nto = [5.0, 2.5, 5.0]\nfov = 40.0\nwidth = 28\nheight = 20\n\
         [[media]]\ndensity = {{ vdb = \"{}\" }}\nsigma_t_scale = 1.0\n",
        p.display()
    );
    normalise(scene(&text), 5.0)
}

fn est(name: &str) -> Estimator {
    Estimator::with_options(name, &Options::default()).unwrap()
}

fn measure(s: &Scene, label: &str) -> Vec<(String, Summary)> {
    let names = [
        "jackknife",
        "jackknife_naive",
        "jackknife_mean_importance",
        "biased_ray_marching",
        "track_length",
        "ratio_tracking",
    ];
    names
        .iter()
        .map(|n| {
            let st = transmittance_stats(
                s,
                est(n),
                Some(Estimator::AnalyticTrilinear(AnalyticTrilinear)),
                RUNS,
                1,
            )
            .summary();
            eprintln!(
                "{label:>8} {n:<26} |bias| {:.5} bias {:+.5} std {:.4} lookups {:.1}",
                st.mean_abs_bias, st.mean_bias, st.mean_std, st.lookups_per_pixel
            );
            (n.to_string(), st)
        })
        .collect()
}

fn check(results: &[(String, Summary)], label: &str) {
    let get = |n: &str| results.iter().find(|(k, _)| k == n).unwrap().1;
    let jk = get("jackknife");
    let naive = get("jackknife_naive");
    let brm = get("biased_ray_marching");
    let tl = get("track_length");
    let rt = get("ratio_tracking");
    let mi = get("jackknife_mean_importance");
    assert!(
        jk.mean_abs_bias <= naive.mean_abs_bias / 3.0,
        "{label}: jackknife |bias| {} vs naive {}",
        jk.mean_abs_bias,
        naive.mean_abs_bias
    );
    assert!(
        jk.mean_abs_bias <= brm.mean_abs_bias / 2.0,
        "{label}: jackknife |bias| {} vs biased RM {}",
        jk.mean_abs_bias,
        brm.mean_abs_bias
    );
    assert!(
        jk.mean_std <= tl.mean_std / 2.0,
        "{label}: jackknife std {} vs track-length {}",
        jk.mean_std,
        tl.mean_std
    );
    assert!(
        jk.mean_std < rt.mean_std,
        "{label}: jackknife std {} vs ratio tracking {}",
        jk.mean_std,
        rt.mean_std
    );
    assert!(
        mi.mean_abs_bias > jk.mean_abs_bias,
        "{label}: mean-importance |bias| {} vs jackknife {}",
        mi.mean_abs_bias,
        jk.mean_abs_bias
    );
}

#[test]
fn jackknife_ordering_on_two_clouds_and_the_dragon() {
    let a = cloud(64, 7);
    check(&measure(&a, "cloud A"), "cloud A");
    let b = cloud(96, 21);
    check(&measure(&b, "cloud B"), "cloud B");
    let d = dragon();
    check(&measure(&d, "dragon"), "dragon");
}

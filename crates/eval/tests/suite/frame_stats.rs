//! The statistics tool itself: an unbiased estimator shows no bias against
//! an exact reference; a biased one does.

use fogbank_estimators::estimator::{
    AnalyticTrilinear, Jackknife, RatioTracking, RayMarching, TrackLength,
};
use fogbank_estimators::Estimator;
use fogbank_eval::transmittance_stats;
use fogbank_render::{parse_scene, Scene};
use std::path::Path;

fn scene() -> Scene {
    let text = "[camera]\nwidth = 20\nheight = 16\nfov = 45.0\n\
                [[media]]\ndensity = { procedural = \"cloud\", resolution = 32, seed = 5 }\nsigma_t_scale = 6.0\n";
    Scene::build(parse_scene(text, "test", &[]).unwrap(), Path::new(".")).unwrap()
}

#[test]
fn unbiased_estimator_has_mean_bias_within_4_se() {
    let s = scene();
    for e in [
        Estimator::RatioTracking(RatioTracking { roulette: 0.0 }),
        Estimator::TrackLength(TrackLength),
    ] {
        let st = transmittance_stats(
            &s,
            e,
            Some(Estimator::AnalyticTrilinear(AnalyticTrilinear)),
            1024,
            3,
        )
        .summary();
        assert!(st.pixels > 50);
        assert!(st.mean_bias_se > 0.0);
        assert!(
            st.mean_bias.abs() < 4.0 * st.mean_bias_se,
            "{}: mean bias {} (se {})",
            e.name(),
            st.mean_bias,
            st.mean_bias_se
        );
    }
}

#[test]
fn biased_estimator_is_flagged() {
    let s = scene();
    let e = Estimator::RayMarching(RayMarching {
        samples: 2,
        clip: false,
    });
    let st = transmittance_stats(
        &s,
        e,
        Some(Estimator::AnalyticTrilinear(AnalyticTrilinear)),
        1024,
        3,
    )
    .summary();
    assert!(
        st.mean_bias > 8.0 * st.mean_bias_se,
        "ray marching mean bias {} (se {})",
        st.mean_bias,
        st.mean_bias_se
    );
}

#[test]
fn statistics_do_not_depend_on_thread_count() {
    let s = scene();
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                transmittance_stats(
                    &s,
                    Estimator::Jackknife(Jackknife {
                        samples: 4,
                        mode: fogbank_estimators::jackknife::StepMode::FixedCount,
                        jitter: fogbank_estimators::optical_depth::Jitter::Stratified,
                    }),
                    None,
                    64,
                    9,
                )
            })
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.mean, b.mean);
    assert_eq!(a.variance, b.variance);
}

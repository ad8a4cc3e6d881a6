//! Peters 2025's (and Hansen 2025's) one-dimensional experiments at reduced trial counts: each test
//! checks the experiment's qualitative finding on the computed numbers.

use fogbank_estimators::optical_depth::Jitter;
use fogbank_experiments::peters2025_jackknife::{
    distributions, fig14, fig2, fig3, fig4, fig5, fig7, profile, table1,
};
use fogbank_experiments::{self as experiments, hansen2025_pins as pins};

#[test]
fn fig2_jackknife_reduces_bias_and_laplace_underestimates() {
    let rows = fig2::compute(200_000, &[0.5, 1.0]);
    assert_eq!(rows.len(), 12);
    for r in &rows {
        // Simulated and exact expectations agree (4 standard errors).
        let se = r.jackknife.std_error();
        assert!(
            (r.jackknife.mean() - r.jackknife_exact.0).abs() < 4.0 * se + 1e-9,
            "{:?} σ={}: {} vs {}",
            r.family,
            r.sigma,
            r.jackknife.mean(),
            r.jackknife_exact.0
        );
        assert!(
            r.jackknife_bias().abs() < r.naive_bias().abs(),
            "{:?} σ={}: jackknife {} naive {}",
            r.family,
            r.sigma,
            r.jackknife_bias(),
            r.naive_bias()
        );
        assert!(r.naive_bias() > 0.0, "Jensen: naive always overestimates");
    }
    for r in rows
        .iter()
        .filter(|r| r.family == distributions::Family::Laplace)
    {
        assert!(
            r.jackknife_bias() + 3.0 * r.jackknife.std_error() < 0.0,
            "Laplace σ={}: {}",
            r.sigma,
            r.jackknife_bias()
        );
        // Exact: E(K) = T/(1 + b⁴/4), b = σ/√2.
        let b = r.sigma / 2f64.sqrt();
        assert!((r.jackknife_exact.0 - r.truth() / (1.0 + b.powi(4) / 4.0)).abs() < 1e-12);
    }
    // Normal inputs: the jackknife is exactly unbiased.
    for r in rows
        .iter()
        .filter(|r| r.family == distributions::Family::Normal)
    {
        assert!((r.jackknife_exact.0 - r.truth()).abs() < 1e-12);
    }
}

#[test]
fn fig3_ratio_at_least_one_and_tends_to_sqrt2() {
    let pts = fig3::compute(100_000, &[0.2, 0.6, 1.0, 1.4, 2.0]);
    for p in &pts {
        assert!(p.ratio() >= 0.995, "σ={}: ratio {}", p.sigma, p.ratio());
        // The MSE's own Monte Carlo error grows like e^{σ²}: compare with
        // App. A only where 10⁵ trials pin it down.
        if p.sigma <= 1.0 {
            assert!(
                (p.jackknife / fig3::jackknife_rrmse(p.sigma) - 1.0).abs() < 0.05,
                "σ={}: {}",
                p.sigma,
                p.jackknife
            );
            assert!(
                (p.naive / fig3::naive_rrmse(p.sigma) - 1.0).abs() < 0.05,
                "σ={}: {}",
                p.sigma,
                p.naive
            );
        }
    }
    let last = pts[pts.len() - 1];
    assert!(
        (last.ratio() - 2f64.sqrt()).abs() < 0.1,
        "ratio at σ=2: {}",
        last.ratio()
    );
    // The closed forms: ≥ 1, increasing, → √2.
    let mut prev = 1.0;
    for k in 1..=60 {
        let s = k as f64 * 0.05;
        let r = fig3::naive_rrmse(s) / fig3::jackknife_rrmse(s);
        assert!(
            r >= 1.0 - 1e-9 && r >= prev - 1e-9 && r < 2f64.sqrt(),
            "σ={s}: {r}"
        );
        prev = r;
    }
    assert!((prev - 2f64.sqrt()).abs() < 0.005);
}

#[test]
fn table1_m2_least_biased_and_least_noisy_jackknife() {
    let (rows, exact) = table1::compute(300_000);
    assert!((exact - profile::PAPER_TABLE1_T).abs() < 1e-9);
    let row = |m: u32| rows.iter().find(|r| r.m == m).copied().expect("row");
    let (m1, m2) = (row(1), row(2));
    assert_eq!((m2.n, m1.n, row(8).n), (12, 24, 3));
    assert!(
        m2.bias().abs() < m1.bias() / 3.0,
        "m=2 bias {} vs m=1 {}",
        m2.bias(),
        m1.bias()
    );
    assert!(
        m1.bias() > 5.0 * m1.stats.std_error(),
        "naive bias {} not significant",
        m1.bias()
    );
    for r in rows.iter().filter(|r| r.m > 2) {
        assert!(
            m2.stats.std() < r.stats.std(),
            "std m=2 {} vs m={} {}",
            m2.stats.std(),
            r.m,
            r.stats.std()
        );
    }
    assert!(m1.stats.std() < m2.stats.std(), "naive slightly less noisy");
}

#[test]
fn fig4_stratified_approaches_normal_uniform_does_not() {
    let (cases, tau) = fig4::compute(100_000, fig4::Variant::Smooth, &[5, 10, 20]);
    let get = |j: Jitter, n: u32| {
        cases
            .iter()
            .find(|c| c.jitter == j && c.n == n)
            .expect("case")
    };
    for c in &cases {
        // Both are unbiased estimators of τ.
        assert!(
            (c.mean - tau).abs() < 5.0 * c.std / (c.sorted.len() as f64).sqrt(),
            "{:?} N={}: {} vs {tau}",
            c.jitter,
            c.n,
            c.mean
        );
    }
    let s: Vec<f64> = [5, 10, 20]
        .iter()
        .map(|&n| get(Jitter::Stratified, n).ks)
        .collect();
    let u: Vec<f64> = [5, 10, 20]
        .iter()
        .map(|&n| get(Jitter::Uniform, n).ks)
        .collect();
    assert!(s[0] > s[1] && s[1] > s[2], "stratified KS {s:?}");
    assert!(s[2] < 0.5 * s[0], "stratified KS {s:?}");
    // Uniform jittered: no improvement from N = 5 to 20, and far from normal.
    assert!(
        u[2] > 0.7 * u[0] && u[2] > 2.0 * s[2],
        "uniform KS {u:?} vs stratified {s:?}"
    );
    let a: Vec<f64> = [5, 10, 20]
        .iter()
        .map(|&n| get(Jitter::Stratified, n).ad)
        .collect();
    assert!(a[0] > a[2], "stratified A² {a:?}");
    // Fig. 6: the sparse profile stays far from normal at N = 20.
    let (sparse, _) = fig4::compute(100_000, fig4::Variant::Sparse, &[20]);
    let st = sparse
        .iter()
        .find(|c| c.jitter == Jitter::Stratified)
        .expect("case");
    assert!(st.ks > 3.0 * s[2], "sparse KS {} vs smooth {}", st.ks, s[2]);
}

#[test]
fn fig5_slopes() {
    let (curves, _) = fig5::compute(2_000, &fig5::sample_counts());
    let slope = |s: fig5::Sampler| curves.iter().find(|c| c.sampler == s).expect("curve").slope;
    let (st, iid, uj) = (
        slope(fig5::Sampler::StratifiedJittered),
        slope(fig5::Sampler::Iid),
        slope(fig5::Sampler::UniformJittered),
    );
    assert!((st + 1.0).abs() < 0.15, "stratified slope {st}");
    assert!((iid + 0.5).abs() < 0.15, "i.i.d. slope {iid}");
    assert!((uj + 1.0).abs() < 0.2, "uniform jittered slope {uj}");
}

#[test]
fn fig5_direct_stratified_matches_alg1() {
    // Alg. 1 with one super-voxel is plain stratified jittered sampling:
    // same mean and variance as the direct sampler.
    let (cases, tau) = fig4::compute(40_000, fig4::Variant::Smooth, &[10]);
    let alg1 = cases
        .iter()
        .find(|c| c.jitter == Jitter::Stratified)
        .expect("case");
    let (curves, _) = fig5::compute(40_000, &[10]);
    let direct = curves
        .iter()
        .find(|c| c.sampler == fig5::Sampler::StratifiedJittered)
        .expect("curve")
        .rmse[0]
        .1;
    let alg1_rmse = ((alg1.mean - tau).powi(2) + alg1.std.powi(2)).sqrt();
    assert!(
        (alg1_rmse / direct - 1.0).abs() < 0.03,
        "Alg. 1 {alg1_rmse} vs direct {direct}"
    );
}

#[test]
fn fig7_jackknife_less_biased_below_line() {
    let grid = fig7::Grid {
        n_tau: 10,
        n_sigma: 10,
        tau_max: 4.0,
        sigma_max: 4.0,
    };
    let cells = fig7::compute(10_000, grid);
    let (sj, sn) = fig7::abs_bias_below_line(&cells);
    assert!(sj < 0.5 * sn, "Σ|bias| jackknife {sj} vs naive {sn}");
    // Small σ well below the line: negligible jackknife bias.
    for c in cells.iter().filter(|c| c.sigma < 1.0 && c.below_line()) {
        assert!(
            c.jackknife_bias.abs() < 0.01,
            "τ={} σ={}: {}",
            c.tau,
            c.sigma,
            c.jackknife_bias
        );
    }
}

#[test]
fn fig14_zero_contributions_fall_with_supervoxel_size() {
    let rows = fig14::compute(20_000, &fig14::SUPERVOXEL_SIZES);
    let z: Vec<f64> = rows.iter().map(|r| r.zero_fraction).collect();
    assert!(z[0] > z[1] && z[1] > z[2], "zero fractions {z:?}");
    assert!(
        z[0] > 0.8,
        "16-voxel super-voxels waste most samples: {z:?}"
    );
    let b: Vec<f64> = rows
        .iter()
        .map(|r| (r.jackknife.mean() - r.exact).abs())
        .collect();
    assert!(
        b[0] > 10.0 * b[2].max(rows[2].jackknife.std_error()),
        "bias {b:?}"
    );
}

#[test]
fn registry_writes_csv_plots_and_summary() {
    let dir = std::env::temp_dir().join(format!("fogbank-exp-{}", std::process::id()));
    let report =
        experiments::run("jackknife-fig3", &dir, Some(2_000)).expect("jackknife-fig3 runs");
    let names: Vec<String> = report
        .files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for f in ["fig3.csv", "fig3.svg", "fig3.png", "summary.md"] {
        assert!(names.iter().any(|n| n == f), "{f} missing from {names:?}");
    }
    let csv = std::fs::read_to_string(dir.join("fig3.csv")).unwrap();
    assert_eq!(csv.lines().count(), 21);
    let svg = std::fs::read_to_string(dir.join("fig3.svg")).unwrap();
    assert!(svg.contains("<text") && svg.contains("sigma"));
    let png = image::open(dir.join("fig3.png"))
        .expect("png decodes")
        .to_rgb8();
    // Text is rasterised: the axis-label region has dark pixels.
    assert!(png.pixels().filter(|p| p.0 == [0, 0, 0]).count() > 1000);
    assert!(experiments::run("nope", &dir, None).is_err());
    assert!(experiments::names().contains(&"jackknife-fig6"));
    std::fs::remove_dir_all(&dir).ok();
}

/// The jackknife experiments' names before every name began with its
/// method's still run, for one release, as the new ones; other names pass
/// through untouched, so an unknown `fig99` is still an error.
#[test]
fn old_experiment_names_map_to_the_new_with_a_notice() {
    let (name, notice) = experiments::current_name("fig3");
    assert_eq!(name, "jackknife-fig3");
    assert!(notice.unwrap().contains("jackknife-fig3"));
    let (name, notice) = experiments::current_name("table1");
    assert_eq!(name, "jackknife-table1");
    assert!(notice.is_some());
    for current in experiments::names() {
        assert_eq!(
            experiments::current_name(current),
            (current.to_string(), None)
        );
    }
    assert_eq!(
        experiments::current_name("fig99"),
        ("fig99".to_string(), None)
    );
    let dir = std::env::temp_dir().join(format!("fogbank-exp-old-{}", std::process::id()));
    assert!(experiments::run("fig99", &dir, None).is_err());
    std::fs::remove_dir_all(&dir).ok();
}

/// Hansen 2025 Fig. 3.4's finding: decomposed rows sit far closer to the
/// exact discrete distribution than rows of the collision matrix, and no
/// sampler beats independent exact samples.
#[test]
fn pins_fig3_4_decomposition_beats_stored_collision_rows() {
    use fogbank_estimators::pins::reference::collision_probabilities;
    use fogbank_math::Pcg32;
    use pins::fig3_4::{total_variation, transmittances, Sampler};
    let t = transmittances();
    let exact = collision_probabilities(&t);
    let tv = |s: Sampler| -> f64 {
        let mut rng = Pcg32::new(11, 2);
        (0..200)
            .map(|_| total_variation(&s.histogram(&t, &mut rng), &exact))
            .sum::<f64>()
            / 200.0
    };
    let (e, m, d, d5) = (
        tv(Sampler::Exact),
        tv(Sampler::Undecomposed),
        tv(Sampler::Decomposed),
        tv(Sampler::DecomposedMask5),
    );
    assert!(
        e < d && d < 0.5 * m && d5 < 0.5 * m,
        "exact {e}, M {m}, I∧H {d}, 5-step {d5}"
    );
}

/// Hansen 2025 Fig. 4.10's measurement runs on a small image: both methods
/// render, times and errors are finite, and PinMS shares one grid.
#[test]
fn pins_instances_measures_both_methods() {
    use pins::instances::measure;
    // The MSE is held net of the reference's own variance and clamped at 0,
    // so the reference needs many more samples than a frame's 16 for the
    // methods' error to stand above it.
    let r = measure(10, 16, 12, 512).unwrap();
    assert!(r.rm_ms > 0.0 && r.pin_ms > 0.0 && r.build_s > 0.0);
    assert!(r.rm_mse.is_finite() && r.pin_mse.is_finite() && r.pin_mse > 0.0);
}

/// Hansen 2025 Fig. 4.9: the default rule (grid ≤ 0.1× the f16 texture)
/// picks the thesis's P for all four of its volumes.
#[test]
fn pins_memory_rule_matches_the_thesis() {
    use pins::memory::{row, THESIS};
    for (name, dims, p, tex, grid) in THESIS {
        let r = row(name, dims);
        assert_eq!(r.positions, p, "{name}");
        assert!(
            (r.texture_mb - tex).abs() < 0.05 * tex,
            "{name}: {}",
            r.texture_mb
        );
        assert!(
            (r.grid_mb - grid).abs() < 0.05 * grid,
            "{name}: {}",
            r.grid_mb
        );
    }
}

/// Every setting of Hansen 2025's ablation experiment builds (keys valid, grids
/// within limits).
#[test]
fn pins_ablation_settings_all_build() {
    use fogbank_experiments::harness::protocol::build;
    let studies = pins::ablation::studies();
    assert!(studies.len() >= 18);
    for (fig, label, set) in studies {
        let small: Vec<String> = set
            .into_iter()
            .chain(["media.0.density.resolution=16".to_string()])
            .collect();
        build(pins::ablation::SCENE, &small).unwrap_or_else(|e| panic!("{fig} {label}: {e}"));
    }
}

/// Every row of Hansen 2025's bias experiment builds for both lightings.
#[test]
fn pins_bias_settings_all_build() {
    use fogbank_experiments::harness::protocol::build;
    for (case, text) in pins::bias::cases() {
        for (label, set) in pins::bias::settings() {
            let small: Vec<String> = set
                .into_iter()
                .chain(["media.0.density.resolution=16".to_string()])
                .collect();
            build(&text, &small).unwrap_or_else(|e| panic!("{case} {label}: {e}"));
        }
    }
}

/// Hansen 2025's boundary-bias study: every method builds on both volumes,
/// and its pixel regions split a disk on the ambient background into
/// brightness thirds, with the silhouette a one-pixel ring.
#[test]
fn pins_boundary_methods_build_and_regions_split_a_disk() {
    use fogbank_experiments::harness::protocol::build;
    for (_, light_label, light) in pins::boundary::LIGHTS {
        let text = pins::boundary::scene(
            "[[media]]\ndensity = { procedural = \"cloud\", resolution = 16, seed = 7 }\n",
            light,
        );
        for (label, set) in pins::boundary::methods(0.08) {
            build(&text, &set).unwrap_or_else(|e| panic!("{light_label}, {label}: {e}"));
        }
    }
    let (w, h) = (64usize, 48usize);
    let img: Vec<[f32; 3]> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 - 32.0, (i / w) as f32 - 24.0);
            let v = if x * x + y * y < 100.0 {
                0.1 + 0.01 * (x + 10.0)
            } else {
                0.02
            };
            [v; 3]
        })
        .collect();
    let r = pins::boundary::Regions::of(&img);
    let object = (0..w * h).filter(|&i| img[i][0] != 0.02).count();
    assert_eq!(r.thirds.iter().map(Vec::len).sum::<usize>(), object);
    assert!(r.thirds.iter().all(|t| t.len() >= object / 3));
    // The darkest third is the disk's left part, the brightest its right.
    let mean_x = |t: &Vec<usize>| t.iter().map(|&i| (i % w) as f64).sum::<f64>() / t.len() as f64;
    assert!(mean_x(&r.thirds[0]) < 28.0 && mean_x(&r.thirds[2]) > 36.0);
    for &i in &r.silhouette {
        let (x, y) = ((i % w) as f32 - 32.0, (i / w) as f32 - 24.0);
        let d = (x * x + y * y).sqrt();
        assert!((8.0..10.0).contains(&d), "silhouette pixel at radius {d}");
    }
    assert!(
        r.silhouette.len() > 30 && r.silhouette.len() < 80,
        "{}",
        r.silhouette.len()
    );
}

//! End-to-end tests of the `fogbank` binary.

use crate::support;

use fogbank::testing::sample_data;
use fogbank::testing::testdata::external_data;
use std::path::Path;
use support::*;
#[test]
fn default_render_writes_exr_with_variance_png_and_stats() {
    let dir = tmp_dir("default");
    run_ok(
        fogbank()
            .current_dir(&dir)
            .args(["render", "--quiet", "--spp", "4", "--stats", "stats.json"])
            .args(SMALL),
    );
    assert!(dir.join("fogbank.png").exists());
    let image = exr::prelude::read_all_flat_layers_from_file(dir.join("fogbank.exr")).unwrap();
    let layer = &image.layer_data[0];
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    for n in ["R", "G", "B", "variance.R", "variance.G", "variance.B"] {
        assert!(
            names.iter().any(|x| x == n),
            "missing channel {n} in {names:?}"
        );
    }
    assert_eq!(layer.size.0 * layer.size.1, 40 * 30);
    let stats = read_json(&dir.join("stats.json"));
    for key in [
        "integrator",
        "estimator",
        "width",
        "height",
        "spp",
        "seed",
        "threads",
        "render_seconds",
        "mean",
        "lookups_per_pixel",
        "nan_samples",
        "inf_samples",
        "peak_memory_bytes",
    ] {
        assert!(stats.get(key).is_some(), "stats.json lacks `{key}`");
    }
    assert_eq!(stats["spp"], 4);
    assert_eq!(stats["width"], 40);
    let mean = stats["mean"][0].as_f64().unwrap();
    assert!(mean > 0.0 && mean.is_finite(), "image mean {mean}");
    assert_eq!(stats["integrator"], "volpath", "the default scene is lit");
    assert!(stats["lookups_per_pixel"].as_f64().unwrap() > 0.0);
}

#[test]
fn bad_set_key_is_an_error_naming_it() {
    run_fails_naming(
        fogbank().args([
            "render",
            "--quiet",
            "-o",
            tmp("x.png").to_str().unwrap(),
            "--set",
            "integrator.estimatr=x",
        ]),
        "estimatr",
    );
}

#[test]
fn integrators_prints_each_registered_table() {
    let out = fogbank().args(["integrators"]).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for (name, params) in fogbank::desc::INTEGRATORS.iter() {
        assert!(
            text.contains(&format!("integrator.type = \"{name}\"")),
            "{name}"
        );
        assert!(
            text.contains(&fogbank::desc::markdown_table(params)),
            "{name}"
        );
    }
    let one = fogbank().args(["integrators", "restir"]).output().unwrap();
    let one = String::from_utf8(one.stdout).unwrap();
    assert!(one.contains("`temporal_cap`") && !one.contains("`rr_depth` | 3 | first bounce"));
    run_fails_naming(fogbank().args(["integrators", "volpth"]), "volpth");
}

/// An integrator that sees shapes only as black occluders says so, unless
/// `--quiet`.
#[test]
fn occluding_integrators_say_what_they_do_with_shapes() {
    let scene = tmp("occluder_scene.toml");
    std::fs::write(
        &scene,
        "[camera]\nwidth = 4\nheight = 3\n\
         [[media]]\ndensity = { procedural = \"cloud\", resolution = 8 }\n\
         [[shapes]]\ntype = \"rectangle\"\nto_world = { translate = [0.0, 0.0, -1.0] }\n\
         [[lights]]\ntype = \"point\"\nposition = [0.0, 1.0, 1.0]\nintensity = [1.0, 1.0, 1.0]\n\
         [integrator]\ntype = \"point_mis\"\n",
    )
    .unwrap();
    let out = tmp("occluder.exr");
    let args = |quiet: bool| {
        let mut v = vec![
            "render",
            scene.to_str().unwrap(),
            "--spp",
            "1",
            "-o",
            out.to_str().unwrap(),
        ];
        if quiet {
            v.push("--quiet");
        }
        v.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let err = String::from_utf8_lossy(&run_ok(fogbank().args(args(false))).stderr).to_string();
    assert!(
        err.contains("point_mis sees the scene's 1 shape(s) as opaque black occluders"),
        "{err}"
    );
    let err = String::from_utf8_lossy(&run_ok(fogbank().args(args(true))).stderr).to_string();
    assert!(!err.contains("occluders"), "{err}");
}

#[test]
fn info_reports_the_dragon() {
    let p = sample_data::committed("dragon.vdb");
    let out = run_ok(fogbank().args(["info", p.to_str().unwrap()]));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("active voxels 19660"), "{text}");
    assert!(text.contains("[16, 1, 35] – [85, 49, 65]"), "{text}");
}

/// `fogbank info` of a NanoVDB file reports what it reports for the
/// OpenVDB file it was converted from.
#[test]
fn info_reports_a_nanovdb_file_as_its_openvdb_source() {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../volume/tests/fixtures");
    let info = |p: &Path| {
        let out = run_ok(fogbank().args(["info", p.to_str().unwrap()]));
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let nv = info(&fixtures.join("nanovdb/fog_zip.nvdb"));
    let v = info(&fixtures.join("vdb/fog_f32_zip.vdb"));
    assert!(
        nv.contains("NanoVDB, 1 grid(s)") && nv.contains("NanoVDB 32.4.2"),
        "{nv}"
    );
    let facts = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| {
                [
                    "index bbox",
                    "active voxels",
                    "active value range",
                    "transform",
                    "    [",
                ]
                .iter()
                .any(|k| l.contains(k))
            })
            .map(str::to_string)
            .collect()
    };
    assert!(facts(&nv).len() >= 7, "{nv}");
    assert_eq!(facts(&nv), facts(&v));
    let bad = tmp("garbage.nvdb");
    std::fs::write(&bad, b"this is not a nanovdb file at all").unwrap();
    run_fails_naming(
        fogbank().args(["info", bad.to_str().unwrap()]),
        "garbage.nvdb",
    );
}

#[test]
fn info_reports_vol_and_rejects_garbage() {
    if let Some(p) = external_data("sigmat.vol") {
        let out = run_ok(fogbank().args(["info", p.to_str().unwrap()]));
        assert!(String::from_utf8_lossy(&out.stdout).contains("16×16×16"));
    }
    let bad = tmp("garbage.vdb");
    std::fs::write(&bad, b"this is not a vdb file at all").unwrap();
    run_fails_naming(
        fogbank().args(["info", bad.to_str().unwrap()]),
        "garbage.vdb",
    );
}

#[test]
fn renders_a_vdb_scene_file_with_relative_paths() {
    let p = sample_data::committed("dragon.vdb");
    let dir = tmp_dir("vdbscene");
    std::fs::copy(&p, dir.join("dragon.vdb")).unwrap();
    std::fs::write(
        dir.join("scene.toml"),
        "[camera]\nfrom = [3.0, 4.0, 12.0]\nto = [5.0, 2.5, 5.0]\nwidth = 32\nheight = 24\n\
         [[media]]\ndensity = { vdb = \"dragon.vdb\" }\nsigma_t_scale = 10.0\n\
         [integrator]\nestimator = \"analytic_trilinear\"\n[render]\nspp = 1\n",
    )
    .unwrap();
    run_ok(fogbank().args([
        "render",
        "--quiet",
        dir.join("scene.toml").to_str().unwrap(),
        "-o",
        dir.join("d.exr").to_str().unwrap(),
        "--stats",
        dir.join("s.json").to_str().unwrap(),
    ]));
    let stats = read_json(&dir.join("s.json"));
    let mean = stats["mean"][0].as_f64().unwrap();
    assert!(mean < 1.0, "the dragon must be visible (mean T {mean})");
}

#[test]
fn ctrl_c_stops_and_still_writes_the_image() {
    let dir = tmp_dir("interrupt");
    let _ = std::fs::remove_file(dir.join("i.exr"));
    // Not `--quiet`: the summary line on stderr says the render was interrupted.
    let mut args = vec![
        "render", "--spp", "1000000", "-o", "i.exr", "--stats", "i.json",
    ];
    args.extend(SMALL);
    let (status, err) = render_then_ctrl_c(&dir, &args);
    assert!(
        status.success(),
        "interrupted render must exit cleanly, got {status}: {err}"
    );
    assert!(err.contains("interrupted after"), "{err}");
    assert!(dir.join("i.exr").exists(), "no image written after Ctrl-C");
    let stats = read_json(&dir.join("i.json"));
    assert_eq!(stats["interrupted"], true);
    assert!(stats["spp"].as_u64().unwrap() < 1_000_000);
}

#[test]
fn stats_reports_no_bias_for_an_unbiased_estimator_and_report_gathers_it() {
    let dir = tmp("stats");
    let _ = std::fs::remove_dir_all(&dir);
    run_ok(
        fogbank()
            .args([
                "stats",
                "--estimator",
                "ratio_tracking",
                "--runs",
                "512",
                "--reference-estimator",
                "analytic_trilinear",
            ])
            .args(["--out", dir.join("rt").to_str().unwrap()])
            .args(SMALL),
    );
    let s = read_json(&dir.join("rt/summary.json"));
    for key in [
        "mean_abs_bias",
        "mean_bias",
        "mean_std",
        "rmse",
        "ms_per_frame",
        "lookups_per_pixel",
        "runs",
    ] {
        assert!(
            s.get(key).is_some_and(|v| !v.is_null()),
            "summary.json lacks `{key}`"
        );
    }
    let (bias, se) = (
        s["mean_bias"].as_f64().unwrap(),
        s["mean_bias_se"].as_f64().unwrap(),
    );
    assert!(
        se > 0.0 && bias.abs() < 4.0 * se,
        "mean bias {bias} (se {se})"
    );
    assert!(dir.join("rt/maps.png").exists() && dir.join("rt/stats.exr").exists());
    run_ok(fogbank().args(["report", dir.to_str().unwrap()]));
    let page = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(page.contains("rt/maps.png") && page.contains("mean_abs_bias"));
}

#[test]
fn compare_flags_a_biased_render_and_reports_every_metric() {
    let dir = tmp_dir("compare");
    let render = |name: &str, estimator: &str, extra: &[&str]| {
        run_ok(
            fogbank()
                .args([
                    "render",
                    TRANSMITTANCE,
                    "--quiet",
                    "--spp",
                    "512",
                    "-o",
                    dir.join(name).to_str().unwrap(),
                ])
                .args(["--set", &format!("integrator.estimator={estimator}")])
                .args(extra)
                .args(SMALL),
        );
    };
    render("ref.exr", "ratio_tracking", &[]);
    render(
        "biased.exr",
        "ray_marching",
        &["--set", "integrator.samples=2"],
    );
    let compare = |a: &str, b: &str| {
        let out = run_ok(fogbank().args([
            "compare",
            dir.join(a).to_str().unwrap(),
            dir.join(b).to_str().unwrap(),
            "--json",
        ]));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let same = compare("ref.exr", "ref.exr");
    assert_eq!(same["rmse"].as_f64(), Some(0.0), "{same}");
    assert_eq!(same["ztest"]["pass"], true, "{same}");
    let biased = compare("ref.exr", "biased.exr");
    for key in ["rmse", "relmse", "smape", "flip", "ztest"] {
        assert!(biased.get(key).is_some(), "no `{key}` in {biased}");
    }
    assert!(biased["rmse"].as_f64().unwrap() > 0.0);
    assert_eq!(
        biased["ztest"]["pass"], false,
        "two-sample ray marching must be flagged: {}",
        biased["ztest"]
    );
}

#[test]
fn experiment_help_lists_every_experiment() {
    let out = run_ok(fogbank().args(["experiment", "--help"]));
    let help = String::from_utf8_lossy(&out.stdout);
    let words: Vec<&str> = help
        .split(|c: char| !c.is_ascii_alphanumeric() && c != '-')
        .collect();
    for name in fogbank_experiments::names() {
        assert!(words.contains(&name), "`{name}` missing from:\n{help}");
    }
}

/// `--frames`: one file per frame; restir carries reservoirs across frames
/// (on the CPU and, with `--device gpu`, on the GPU); a missing per-frame
/// file stops the sequence with the frames before it written; a scene
/// without animation is refused.
#[test]
fn frames_render_a_sequence_and_stop_at_a_missing_frame() {
    let dir = tmp_dir("frames");
    let scene = animated_raw_scene(
        &dir,
        &[0, 1, 3],
        (12, 8),
        "type = \"restir\"\nmax_depth = 2",
        4,
    );
    let gpu = fogbank::testing::test_gpu().is_some();
    for device in ["cpu", "gpu"].into_iter().filter(|d| *d == "cpu" || gpu) {
        let out = dir.join(format!("{device}_{{frame:02}}.exr"));
        let o = fogbank()
            .args([
                "render",
                scene.to_str().unwrap(),
                "--frames",
                "0..4",
                "--device",
                device,
                "-q",
                "-o",
            ])
            .arg(&out)
            .output()
            .unwrap();
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("frame 2") && err.contains("d_2.raw"),
            "{device}: {err}"
        );
        assert!(!err.contains("panicked"), "{device}: {err}");
        for f in 0..2 {
            let img = fogbank::image::read_image(dir.join(format!("{device}_{f:02}.exr"))).unwrap();
            assert_eq!((img.width, img.height), (12, 8));
            let mean = img.rgb.iter().map(|p| p[1] as f64).sum::<f64>() / img.rgb.len() as f64;
            assert!(
                mean.is_finite() && mean > 0.0,
                "{device} frame {f}: mean {mean}"
            );
        }
        assert!(!dir.join(format!("{device}_02.exr")).exists());
    }
    run_fails_naming(
        fogbank().args(["render", "--frames", "0..2", "-q"]),
        "no [animation]",
    );
    run_fails_naming(
        fogbank().args(["render", scene.to_str().unwrap(), "--frames", "2..9", "-q"]),
        "frames 0..=3",
    );
}

#[test]
fn bench_scaling_table_reports_medians_of_paired_rounds() {
    let out = fogbank()
        .args([
            "bench",
            "--resolution",
            "16",
            "--size",
            "8",
            "--frames",
            "1",
            "--estimators",
            "track_length",
            "--stats-size",
            "0",
            "--threads",
            "1,2",
            "--integrators",
            "transmittance,direct",
            "--repeat",
            "3",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("ms/frame (median of 3)"), "{text}");
    for name in ["transmittance", "direct"] {
        let rows: Vec<Vec<&str>> = text
            .lines()
            .filter(|l| l.starts_with(&format!("| {name} |")))
            .map(|l| l.split('|').map(str::trim).collect())
            .collect();
        assert_eq!(rows.len(), 2, "{text}");
        assert_eq!((rows[0][2], rows[1][2]), ("1", "2"));
        assert_eq!(rows[0][5], "1.00×", "the first count is the baseline");
        let (lo, hi) = rows[1][4].split_once('–').expect("a min–max range");
        let median: f64 = rows[1][3].parse().unwrap();
        let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
        assert!(lo <= median && median <= hi, "{text}");
        let speedup: f64 = rows[1][5].trim_end_matches('×').parse().unwrap();
        assert!(speedup.is_finite() && speedup > 0.0, "{text}");
    }
}

/// Output into a pipe whose reader has gone (`fogbank estimators | head
/// -0`) ends the program quietly instead of with a panic.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_is_no_panic() {
    use std::process::Stdio;
    let mut child = fogbank()
        .args(["estimators"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the read end before the program writes its first line.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

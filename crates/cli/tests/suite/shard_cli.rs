//! `--shard I/N` and `fogbank merge` end to end: merged EXRs (mean and
//! variance layers) and `stats` files equal the single run's byte for byte,
//! for sample-range and tile shards; refusals are clear errors; an
//! interrupted shard leaves no partial behind.

use crate::support;

use std::path::Path;
use support::*;

fn shards_then_merge(dir: &Path, cmd: &[&str], n: u32, mode: &str) -> Vec<String> {
    let parts: Vec<String> = (0..n)
        .map(|i| {
            let part = dir.join(format!("{mode}_{i}.fbpart"));
            let shard = format!("{i}/{n}");
            run_ok(fogbank().args(cmd).args([
                "--shard",
                &shard,
                "--shard-mode",
                mode,
                "-o",
                part.to_str().unwrap(),
            ]));
            part.display().to_string()
        })
        .collect();
    parts
}

fn same_bytes(a: &Path, b: &Path) {
    let (x, y) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    assert!(x == y, "{} and {} differ", a.display(), b.display());
}

#[test]
fn merged_render_shards_equal_the_single_run_byte_for_byte() {
    let dir = tmp_dir("shards");
    for integrator in ["transmittance", "volpath"] {
        let set = format!("integrator.type={integrator}");
        let mut cmd = vec![
            "render",
            TRANSMITTANCE,
            "--quiet",
            "--spp",
            "6",
            "--set",
            &set,
        ];
        cmd.extend(SMALL);
        let single = dir.join(format!("{integrator}_single.exr"));
        run_ok(fogbank().args(&cmd).args(["-o", single.to_str().unwrap()]));
        for mode in ["samples", "tiles"] {
            let parts = shards_then_merge(&dir, &cmd, 4, mode);
            let merged = dir.join(format!("{integrator}_{mode}.exr"));
            let all = dir.join(format!("{integrator}_{mode}.fbpart"));
            run_ok(fogbank().arg("merge").args(&parts).args([
                "-o",
                merged.to_str().unwrap(),
                "-o",
                all.to_str().unwrap(),
                "--stats",
                dir.join("merge.json").to_str().unwrap(),
            ]));
            same_bytes(&merged, &single);
            // A merged partial merges again (alone) to the same image.
            let again = dir.join(format!("{integrator}_{mode}_again.exr"));
            run_ok(fogbank().args([
                "merge",
                all.to_str().unwrap(),
                "-o",
                again.to_str().unwrap(),
            ]));
            same_bytes(&again, &single);
            let stats = read_json(&dir.join("merge.json"));
            assert_eq!(stats["shards"].as_array().unwrap().len(), 4);
            assert_eq!(stats["spp"], 6);
        }
    }
}

#[test]
fn merged_stats_shards_equal_the_single_run() {
    let dir = tmp_dir("stats_shards");
    let single = dir.join("single");
    let mut cmd = vec!["stats", TRANSMITTANCE, "--runs", "8"];
    cmd.extend(SMALL);
    run_ok(
        fogbank()
            .args(&cmd)
            .args(["--out", single.to_str().unwrap()]),
    );
    for mode in ["samples", "tiles"] {
        let out = dir.join(mode);
        let _ = std::fs::remove_dir_all(&out);
        let parts: Vec<String> = (0..4)
            .map(|i| {
                let shard = format!("{i}/4");
                run_ok(fogbank().args(&cmd).args([
                    "--out",
                    out.to_str().unwrap(),
                    "--shard",
                    &shard,
                    "--shard-mode",
                    mode,
                ]));
                out.join(format!("shard_{i}_of_4.fbpart"))
                    .display()
                    .to_string()
            })
            .collect();
        let merged = dir.join(format!("{mode}_merged"));
        run_ok(
            fogbank()
                .arg("merge")
                .args(&parts)
                .args(["-o", merged.to_str().unwrap()]),
        );
        same_bytes(&merged.join("stats.exr"), &single.join("stats.exr"));
        let (a, b) = (
            read_json(&merged.join("summary.json")),
            read_json(&single.join("summary.json")),
        );
        for key in [
            "runs",
            "covered_pixels",
            "mean_std",
            "mean_bias_se",
            "width",
        ] {
            assert_eq!(a[key], b[key], "{key}");
        }
    }
}

#[test]
fn shard_refusals_name_what_is_wrong() {
    let dir = tmp_dir("shard_refusals");
    let part = dir.join("p.fbpart");
    let p = part.to_str().unwrap();
    let base = ["render", TRANSMITTANCE, "--quiet", "--spp", "4"];
    let refused = |extra: &[&str], needle: &str| {
        run_fails_naming(fogbank().args(base).args(SMALL).args(extra), needle)
    };
    refused(&["--shard", "4/4", "-o", p], "0 ≤ I < N");
    refused(&["--shard", "x", "-o", p], "expected I/N");
    refused(
        &["--shard", "0/2", "--shard-mode", "rows", "-o", p],
        "samples or tiles",
    );
    refused(&["--shard", "0/2", "-o", "x.exr"], "must end in .fbpart");
    refused(
        &["--shard", "0/2", "-o", p, "--time-budget", "2"],
        "--time-budget",
    );
    refused(
        &["--shard", "0/2", "-o", p, "--device", "gpu"],
        "--device gpu",
    );
    refused(
        &["--shard", "0/2", "-o", p, "--set", "integrator.type=restir"],
        "restir",
    );
    run_fails_naming(
        fogbank().args([
            "stats",
            TRANSMITTANCE,
            "--shard",
            "0/2",
            "--reference-estimator",
            "analytic_trilinear",
        ]),
        "not with a reference",
    );
    // merge: a damaged file is named; missing shards are listed.
    run_ok(
        fogbank()
            .args(base)
            .args(SMALL)
            .args(["--shard", "0/2", "-o", p]),
    );
    let mut bytes = std::fs::read(&part).unwrap();
    let whole = bytes.clone();
    bytes.truncate(bytes.len() / 2);
    let broken = dir.join("broken.fbpart");
    std::fs::write(&broken, &bytes).unwrap();
    run_fails_naming(
        fogbank().args(["merge", broken.to_str().unwrap(), "-o", "x.exr"]),
        "broken.fbpart: checksum mismatch",
    );
    run_fails_naming(
        fogbank().args(["merge", p, p, "-o", "x.exr"]),
        "duplicate shard 0/2",
    );
    run_fails_naming(
        fogbank().args(["merge", p, "-o", "x.exr"]),
        "shard 1/2 (samples 2..4)",
    );
    std::fs::write(&part, whole).unwrap();
    let out = dir.join("partial.exr");
    run_ok(fogbank().args(["merge", p, "--allow-partial", "-o", out.to_str().unwrap()]));
    assert!(out.exists());
}

#[test]
fn an_interrupted_shard_writes_no_partial() {
    let dir = tmp_dir("shard_interrupt");
    let _ = std::fs::remove_file(dir.join("i.fbpart"));
    let mut args = vec![
        "render", "--spp", "1000000", "--shard", "0/2", "-o", "i.fbpart",
    ];
    args.extend(SMALL);
    let (status, err) = render_then_ctrl_c(&dir, &args);
    assert!(!status.success(), "{err}");
    assert!(err.contains("wrote no partial"), "{err}");
    assert!(!dir.join("i.fbpart").exists());
    assert!(!dir.join("i.fbpart.tmp").exists());
}

/// `--frames` with `--shard`: a partial per frame; each frame's parts merge
/// to that frame of the unsharded sequence, and parts of different frames
/// are refused.
#[test]
fn sharded_frame_sequences_merge_per_frame() {
    let dir = tmp_dir("shard_frames");
    let scene = animated_raw_scene(
        &dir,
        &[0, 1],
        (40, 36),
        "type = \"volpath\"\nmax_depth = 3",
        2,
    );
    let s = scene.to_str().unwrap();
    let single = dir.join("single_{frame}.exr");
    run_ok(
        fogbank()
            .args(["render", s, "--frames", "0..2", "--spp", "5", "-q", "-o"])
            .arg(&single),
    );
    for i in 0..3 {
        let shard = format!("{i}/3");
        let out = dir.join(format!("part_{{frame}}_{i}.fbpart"));
        run_ok(
            fogbank()
                .args([
                    "render", s, "--frames", "0..2", "--spp", "5", "-q", "--shard", &shard, "-o",
                ])
                .arg(&out),
        );
    }
    let part = |f: u32, i: u32| {
        dir.join(format!("part_{f}_{i}.fbpart"))
            .display()
            .to_string()
    };
    for f in 0..2 {
        let merged = dir.join(format!("merged_{f}.exr"));
        run_ok(
            fogbank()
                .args(["merge", &part(f, 0), &part(f, 1), &part(f, 2), "-o"])
                .arg(&merged),
        );
        same_bytes(&merged, &dir.join(format!("single_{f}.exr")));
    }
    run_fails_naming(
        fogbank().args([
            "merge",
            &part(0, 0),
            &part(1, 1),
            &part(0, 2),
            "-o",
            "x.exr",
        ]),
        "frame 1 differs",
    );
}
